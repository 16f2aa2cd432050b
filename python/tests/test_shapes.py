"""Shapes: rays of any leading shape ((H, W, 3), one (3,) ray) and points likewise give results of
that shape; max_distance per point; out= on every query, checked."""
import numpy as np
import pytest

import arbor
from conftest import random_rays


def test_ray_grids_give_results_of_their_shape(spot):
    s = arbor.Scene.load(spot)
    s.build("bvh-sah")
    o, d = random_rays(s, 24, seed=41)
    flat = s.intersect(o, d)
    assert 0 < np.count_nonzero(flat["prim"] != arbor.MISS) < 24
    grid = s.intersect(o.reshape(4, 6, 3), d.reshape(4, 6, 3))
    assert grid.shape == (4, 6) and grid.tobytes() == flat.tobytes()
    assert s.occluded(o.reshape(2, 3, 4, 3), d.reshape(2, 3, 4, 3), tfar=np.full((2, 3, 4), 9.0)).shape == (2, 3, 4)
    rows, counts = s.intersect_all(o.reshape(4, 6, 3), d.reshape(4, 6, 3), max_hits=3)
    ref_rows, ref_counts = s.intersect_all(o, d, max_hits=3)
    assert rows.shape == (4, 6, 3) and counts.shape == (4, 6)
    assert rows.tobytes() == ref_rows.tobytes() and counts.tobytes() == ref_counts.tobytes()
    # One ray: a 0-d record; broadcasting as numpy does it (one origin, a (H, W) grid of directions).
    one = s.intersect(o[3], d[3])
    assert one.shape == () and one.tobytes() == flat[3].tobytes() and float(one["t"]) == flat["t"][3]
    fan = s.intersect(o[0], d.reshape(4, 6, 3))
    assert fan.shape == (4, 6) and fan.tobytes() == s.intersect(np.repeat(o[:1], 24, 0), d).tobytes()
    outer = s.intersect(o[:4].reshape(4, 1, 3), d[:6].reshape(1, 6, 3))
    assert outer.shape == (4, 6)
    want = s.intersect(np.repeat(o[:4], 6, 0), np.tile(d[:6], (4, 1))).reshape(4, 6)
    assert outer.tobytes() == want.tobytes()
    # tnear / tfar per ray take the rays' shape.
    assert s.intersect(o.reshape(4, 6, 3), d.reshape(4, 6, 3), tfar=np.full((4, 6), 0.5)).shape == (4, 6)
    with pytest.raises(ValueError, match=r"tfar: expected a number or shape \(4, 6\) \(one per ray\), got \(24,\)"):
        s.intersect(o.reshape(4, 6, 3), d.reshape(4, 6, 3), tfar=np.full(24, 0.5))
    with pytest.raises(ValueError, match=r"directions: expected a shape that broadcasts with origins' \(4, 6\)"):
        s.intersect(o.reshape(4, 6, 3), d.reshape(6, 4, 3))


def test_points_of_any_shape_and_one_point(box_scene):
    p = np.array([[0, 0, -3], [0.5, 0.25, 0], [0, 0, 0.5], [5, 5, 5]], np.float32)
    flat = box_scene.closest_point(p)
    grid = box_scene.closest_point(p.reshape(2, 2, 3))
    assert grid.shape == (2, 2) and grid.tobytes() == flat.tobytes()
    one = box_scene.closest_point(p[0])
    assert one.shape == () and one.dtype == arbor.point_dtype and float(one["distance"]) == pytest.approx(2.0)
    assert box_scene.inside(p.reshape(2, 2, 3)).tolist() == [[False, True], [True, False]]
    inside_one = box_scene.inside([0.0, 0.0, 0.0])
    assert inside_one.shape == () and bool(inside_one)


def test_max_distance_is_a_number_or_one_per_point(box_scene):
    p = np.array([[0, 0, -3], [0, 0, -3], [0, 0, 3]], np.float32)  # 2 from the box each
    res = box_scene.closest_point(p, max_distance=np.array([1.0, 2.5, np.inf]))
    assert np.isinf(res["distance"][0]) and res["prim"][0] == arbor.MISS
    np.testing.assert_allclose(res["distance"][1:], [2.0, 2.0])
    assert box_scene.closest_point(p, [3, 1, 3])["prim"].tolist()[1] == arbor.MISS
    # What a new user passed: an array of 2 for 3 points, a size-1 array, a bad value.
    for bad in (np.array([1.0, 2.0]), np.array([1.0]), [[1.0, 2.0, 3.0]]):
        with pytest.raises(ValueError, match=r"^max_distance: expected a number or shape \(3,\) \(one per point\), got"):
            box_scene.closest_point(p, max_distance=bad)
    with pytest.raises(ValueError, match=r"^max_distance: expected numbers >= 0 \(inf: no limit\), got -1.0 at flat index 2$"):
        box_scene.closest_point(p, max_distance=np.array([1.0, 2.0, -1.0]))
    with pytest.raises(ValueError, match=r"max_distance: expected numbers >= 0 .*got nan at flat index 0"):
        box_scene.closest_point(p, max_distance=np.array([np.nan, 2.0, 1.0]))
    with pytest.raises(TypeError, match=r"^max_distance: expected a number, got str$"):
        box_scene.closest_point(p, max_distance="far")
    # A single point takes a number (or a 0-d array).
    assert float(box_scene.closest_point(p[0], max_distance=np.array(2.5))["distance"]) == pytest.approx(2.0)


OUT_CASES = {
    "closest_point": (lambda s, out: s.closest_point(np.zeros((4, 3), np.float32) + 3, out=out), arbor.point_dtype,
                      "arbor.point_dtype"),
    "inside": (lambda s, out: s.inside(np.zeros((4, 3), np.float32), out=out), np.dtype(bool), "bool"),
    "occluded": (lambda s, out: s.occluded(np.zeros((4, 3), np.float32) - 5, [0, 0, 1.0], out=out), np.dtype(bool), "bool"),
}


@pytest.mark.parametrize("call", sorted(OUT_CASES))
def test_out_on_point_queries_is_written_and_checked(box_scene, call):
    f, dtype, name = OUT_CASES[call]
    ref = f(box_scene, None)
    out = np.zeros(4, dtype) if dtype != bool else ~ref
    assert f(box_scene, out) is out and out.tobytes() == ref.tobytes()
    with pytest.raises(TypeError, match=f"^out: expected a numpy array of dtype {name} and shape \\(4,\\), got dtype float64$"):
        f(box_scene, np.zeros(4))
    with pytest.raises(ValueError, match=r"^out: expected .* and shape \(4,\), got shape \(2, 2\)$"):
        f(box_scene, np.zeros((2, 2), dtype))
    with pytest.raises(ValueError, match="^out: expected a contiguous array"):
        f(box_scene, np.zeros(8, dtype)[::2])
    ro = np.zeros(4, dtype)
    ro.flags.writeable = False
    with pytest.raises(ValueError, match="^out: the array is read-only$"):
        f(box_scene, ro)


def test_out_of_the_grid_shape(box_scene):
    p = np.zeros((2, 3, 3), np.float32)
    out = np.empty((2, 3), bool)
    assert box_scene.inside(p, out=out) is out and out.all()
    with pytest.raises(ValueError, match=r"out: expected .* shape \(2, 3\), got shape \(6,\)"):
        box_scene.inside(p, out=np.empty(6, bool))
    single = np.empty((), arbor.point_dtype)
    assert box_scene.closest_point([0, 0, 3], out=single) is single and float(single["distance"]) == pytest.approx(2.0)


def test_out_on_intersect_all(spot):
    s = arbor.Scene.load(spot)
    s.build("bvh-sah")
    o, d = random_rays(s, 300, seed=42)
    ref_rows, ref_counts = s.intersect_all(o, d, max_hits=4)
    assert np.count_nonzero(ref_counts >= 2) > 20
    rows = np.frombuffer(np.random.default_rng(3).bytes(300 * 4 * arbor.hit_dtype.itemsize), arbor.hit_dtype).reshape(300, 4).copy()
    counts = np.full(300, -7, np.int32)
    res = s.intersect_all(o, d, max_hits=4, out=(rows, counts))
    assert res[0] is rows and res[1] is counts
    assert rows.tobytes() == ref_rows.tobytes() and counts.tobytes() == ref_counts.tobytes()
    with pytest.raises(TypeError, match=r"^out: expected a tuple \(hits, counts\) of numpy arrays of shapes \(300, 4\) and \(300,\), got ndarray$"):
        s.intersect_all(o, d, max_hits=4, out=rows)
    with pytest.raises(ValueError, match=r"^out: expected a tuple \(hits, counts\) of two numpy arrays, got 3 items$"):
        s.intersect_all(o, d, max_hits=4, out=(rows, counts, counts))
    with pytest.raises(ValueError, match=r"^out\[0\]: expected .* shape \(300, 4\), got shape \(300, 3\)$"):
        s.intersect_all(o, d, max_hits=4, out=(rows[:, :3], counts))
    with pytest.raises(TypeError, match=r"^out\[1\]: expected a numpy array of dtype int32 .*, got dtype int64$"):
        s.intersect_all(o, d, max_hits=4, out=(rows, counts.astype(np.int64)))
    with pytest.raises(ValueError, match=r"^out\[1\]: shares memory with an input array"):
        s.intersect_all(o, d, max_hits=4, out=(rows, rows.view(np.int32).reshape(-1)[:300]))
