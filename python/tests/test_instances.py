"""Instances (Scene.add_instance, set_transform): records gain inst, answers agree with the scene
flattened by numpy, and bad geometry ids and transforms raise TypeError or ValueError naming the
argument."""
import numpy as np
import pytest

import arbor
from conftest import box_mesh


def rotation(angle, axis):
    a = np.asarray(axis, np.float64) / np.linalg.norm(axis)
    k = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * (k @ k)


TRANSFORMS = [
    np.hstack([rotation(0.7, (1, 2, 3)), [[4], [0], [0]]]),
    np.hstack([rotation(2.0, (0, 1, 1)) @ np.diag([-1.0, 1, 1]), [[0], [4], [0.5]]]),  # mirror
    np.hstack([rotation(1.1, (1, 0, 1)) @ np.diag([0.5, 1.5, 0.8]), [[-4], [0], [1]]]),  # non-uniform scale
]


def scenes():
    v, f = box_mesh()
    placed = arbor.Scene(v, f)
    flat = arbor.Scene()
    for k, t in enumerate(TRANSFORMS):
        assert placed.add_instance(0, t) == k
        w = (v.astype(np.float64) @ t[:, :3].T + t[:, 3]).astype(np.float32)
        flat.add_mesh(w, f)
    return placed, flat


def test_hits_have_inst_and_agree_with_the_flattened_scene():
    placed, flat = scenes()
    assert placed.instances == 3
    rng = np.random.default_rng(3)
    targets = np.concatenate([t[:, 3] + rng.uniform(-0.7, 0.7, (300, 3)) for t in TRANSFORMS]).astype(np.float32)
    origins = (targets + rng.normal(size=targets.shape) * 6).astype(np.float32)
    dirs = targets - origins
    a, b = flat.intersect(origins, dirs), placed.intersect(origins, dirs)
    assert b.dtype == arbor.hit_inst_dtype
    assert a.dtype == arbor.hit_dtype
    hit = a["prim"] != arbor.MISS
    assert hit.sum() > 500
    # The box's faces are two triangles: rays near a diagonal may pick either; compare the face.
    assert np.array_equal(b["prim"] != arbor.MISS, hit)
    assert np.array_equal(b["inst"][hit], a["geom"][hit])
    assert np.all(b["inst"][~hit] == arbor.MISS)
    assert np.all(b["geom"][hit] == 0)
    assert np.array_equal(b["prim"][hit] // 2, a["prim"][hit] // 2)
    np.testing.assert_allclose(b["t"][hit], a["t"][hit], rtol=1e-5, atol=1e-5)
    assert np.array_equal(placed.occluded(origins, dirs), flat.occluded(origins, dirs))
    hits, counts = placed.intersect_all(origins, dirs, max_hits=4)
    assert hits.dtype == arbor.hit_inst_dtype
    assert np.array_equal(counts, flat.intersect_all(origins, dirs, max_hits=4)[1])
    with_n = placed.intersect(origins, dirs, normals=True)
    assert with_n.dtype == arbor.hit_inst_normal_dtype
    flat_n = flat.intersect(origins, dirs, normals=True)
    np.testing.assert_allclose(with_n["normal"][hit], flat_n["normal"][hit], atol=1e-5)
    near, far = placed.closest_point(targets), flat.closest_point(targets)
    assert near.dtype == arbor.point_inst_dtype
    np.testing.assert_allclose(near["distance"], far["distance"], rtol=1e-5, atol=1e-6)
    assert np.array_equal(near["inst"], far["geom"])
    inside = np.abs(far["distance"]) > 1e-3
    assert np.array_equal(placed.inside(targets)[inside], flat.inside(targets)[inside])


def test_set_transform_moves_an_instance_and_out_arrays_take_the_inst_dtype():
    v, f = box_mesh()
    s = arbor.Scene(v, f)
    s.add_instance(0, np.eye(3, 4, dtype=np.float32))
    o, d = np.float32([[0, 0, -5]]), np.float32([[0, 0, 1]])
    assert s.intersect(o, d)["t"][0] == 4.0
    s.set_transform(0, [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 2]])
    assert s.intersect(o, d)["t"][0] == 6.0
    out = np.empty(1, arbor.hit_inst_dtype)
    s.intersect(o, d, out=out)
    assert out["inst"][0] == 0 and out["t"][0] == 6.0
    with pytest.raises(TypeError, match="arbor.hit_inst_dtype"):
        s.intersect(o, d, out=np.empty(1, arbor.hit_dtype))


@pytest.mark.parametrize("transform, error, match", [
    (np.full((3, 4), np.nan), ValueError, r"transform: entry \[0\]\[0\] is not finite"),
    (np.array([[1, 0, 0, np.inf], [0, 1, 0, 0], [0, 0, 1, 0]]), ValueError, r"transform: entry \[0\]\[3\] is not finite"),
    (np.zeros((3, 4)), ValueError, "transform: the 3x3 part is singular"),
    (np.eye(4), ValueError, r"transform: expected shape \(3, 4\).*got \(4, 4\)"),
    (np.eye(3), ValueError, r"transform: expected shape \(3, 4\)"),
    (np.ones(12), ValueError, r"transform: expected shape \(3, 4\).*got \(12,\)"),
    (np.full((3, 4), "x"), TypeError, "transform: expected a \\(3, 4\\) array of floats"),
    (np.eye(3, 4) * 1j, TypeError, "transform: expected a \\(3, 4\\) array of floats"),
    ("identity", TypeError, "transform: expected a \\(3, 4\\) array of floats"),
    (None, TypeError, "transform: expected a \\(3, 4\\) array of floats"),
])
def test_bad_transforms_raise_naming_the_argument(transform, error, match):
    v, f = box_mesh()
    s = arbor.Scene(v, f)
    with pytest.raises(error, match=match):
        s.add_instance(0, transform)
    s.add_instance(0, np.eye(3, 4))
    with pytest.raises(error, match=match):
        s.set_transform(0, transform)
    assert s.instances == 1


def test_unknown_ids_raise_naming_the_argument():
    v, f = box_mesh()
    s = arbor.Scene(v, f)
    with pytest.raises(ValueError, match="add_instance: geom 1 is not in the scene"):
        s.add_instance(1, np.eye(3, 4))
    with pytest.raises(ValueError, match="geom"):
        s.add_instance(-1, np.eye(3, 4))
    with pytest.raises(TypeError, match="geom"):
        s.add_instance("0", np.eye(3, 4))
    with pytest.raises(ValueError, match="set_transform: instance 0 is not in the scene"):
        s.set_transform(0, np.eye(3, 4))
    with pytest.raises(TypeError, match="inst"):
        s.set_transform(0.5, np.eye(3, 4))
    assert s.instances == 0
    assert s.intersect(np.float32([0, 0, -5]), np.float32([0, 0, 1])).dtype == arbor.hit_dtype
