"""What hits carry: normals=True adds the unit geometric normal, and (u, v) are the weights of the
triangle's second and third corners, as Embree's and Open3D's primitive_uvs are."""
import numpy as np
import pytest

import arbor
from conftest import box_mesh, random_rays


def two_meshes():
    """A sphere-ish mesh (a box with jittered vertices) and a tilted box: two geometry ids."""
    v, f = box_mesh()
    rng = np.random.default_rng(7)
    v1 = (v + rng.normal(scale=0.1, size=v.shape)).astype(np.float32)
    rot = np.array([[0.8, -0.6, 0], [0.6, 0.8, 0], [0, 0, 1]], np.float32)
    v2 = (v * np.float32(0.5) @ rot.T + np.float32([3, 0.5, 0.2])).astype(np.float32)
    return [(v1, f), (v2, f)]


def numpy_normals(meshes, hits):
    n = np.zeros((len(hits), 3))
    for g, (v, f) in enumerate(meshes):
        sel = (hits["geom"] == g) & (hits["prim"] != arbor.MISS)
        tri = v[f[hits["prim"][sel]]].astype(np.float64)
        c = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
        n[sel] = c / np.linalg.norm(c, axis=1, keepdims=True)
    return n


def scene_of(meshes):
    s = arbor.Scene(*meshes[0])
    for v, f in meshes[1:]:
        s.add_mesh(v, f)
    s.build("bvh-sah")
    return s


def test_normals_are_the_unit_geometric_normals_numpy_computes():
    meshes = two_meshes()
    s = scene_of(meshes)
    o, d = random_rays(s, 4000, seed=31)
    plain = s.intersect(o, d)
    h = s.intersect(o, d, normals=True)
    assert h.dtype == arbor.hit_normal_dtype and h.dtype.names == ("t", "geom", "prim", "u", "v", "normal")
    assert h.dtype["normal"] == np.dtype(("<f4", (3,)))
    # The hit fields are those of a call without normals, bit for bit.
    for name in plain.dtype.names:
        assert h[name].tobytes() == plain[name].tobytes(), name
    hit = h["prim"] != arbor.MISS
    assert np.count_nonzero(hit[h["geom"] == 0]) > 300 and np.count_nonzero(h["geom"] == 1) > 100
    assert np.count_nonzero(~hit) > 100
    np.testing.assert_allclose(h["normal"], numpy_normals(meshes, h), atol=2e-7)
    assert np.all(h["normal"][~hit] == 0)
    np.testing.assert_allclose(np.linalg.norm(h["normal"][hit], axis=1), 1, atol=1e-6)
    # Rays from outside meet these outward-wound closed boxes at a face that faces them.
    assert np.all(np.einsum("ij,ij->i", h["normal"][hit], d[hit]) < 0)


def test_intersect_all_normals_and_out():
    meshes = two_meshes()
    s = scene_of(meshes)
    o, d = random_rays(s, 500, seed=32)
    rows, counts = s.intersect_all(o, d, max_hits=4, normals=True)
    plain_rows, plain_counts = s.intersect_all(o, d, max_hits=4)
    assert rows.dtype == arbor.hit_normal_dtype and rows.shape == (500, 4)
    assert np.array_equal(counts, plain_counts) and np.count_nonzero(counts >= 2) > 50
    for name in plain_rows.dtype.names:
        assert rows[name].tobytes() == plain_rows[name].tobytes(), name
    flat = rows.reshape(-1)
    np.testing.assert_allclose(flat["normal"], numpy_normals(meshes, flat), atol=2e-7)
    # out= of the normal dtype, written in place (whatever it held) and returned.
    out = np.frombuffer(np.random.default_rng(2).bytes(500 * arbor.hit_normal_dtype.itemsize), arbor.hit_normal_dtype).copy()
    assert s.intersect(o, d, out=out, normals=True) is out
    assert out.tobytes() == s.intersect(o, d, normals=True).tobytes()
    with pytest.raises(TypeError, match="out: expected a numpy array of dtype arbor.hit_normal_dtype"):
        s.intersect(o, d, out=np.empty(500, arbor.hit_dtype), normals=True)
    with pytest.raises(TypeError, match="normals: expected a bool, got int"):
        s.intersect(o, d, normals=1)


def test_u_v_weight_the_second_and_third_corner():
    # hit point = (1-u-v) v0 + u v1 + v v2 (Embree's convention, and Open3D's primitive_uvs): the
    # point rebuilt from (prim, u, v) is the point o + t d where the ray hit.
    meshes = two_meshes()
    s = scene_of(meshes)
    o, d = random_rays(s, 3000, seed=33)
    h = s.intersect(o, d)
    hit = h["prim"] != arbor.MISS
    along = o[hit] + h["t"][hit, None] * d[hit]
    rebuilt = np.zeros_like(along)
    for g, (v, f) in enumerate(meshes):
        sel = h["geom"][hit] == g
        tri = v[f[h["prim"][hit][sel]]]
        u, w = h["u"][hit][sel, None], h["v"][hit][sel, None]
        rebuilt[sel] = (1 - u - w) * tri[:, 0] + u * tri[:, 1] + w * tri[:, 2]
    assert np.all((h["u"][hit] >= 0) & (h["v"][hit] >= 0) & (h["u"][hit] + h["v"][hit] <= 1 + 1e-6))
    np.testing.assert_allclose(rebuilt, along, atol=5e-5)
    # The other orders would put the points elsewhere: the test tells them apart.
    tri = meshes[0][0][meshes[0][1][h["prim"][hit & (h["geom"] == 0)]]]
    u, w = h["u"][hit & (h["geom"] == 0), None], h["v"][hit & (h["geom"] == 0), None]
    swapped = (1 - u - w) * tri[:, 0] + w * tri[:, 1] + u * tri[:, 2]
    assert np.max(np.abs(swapped - along[h["geom"][hit] == 0])) > 1e-2
