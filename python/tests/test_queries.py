"""The queries: every structure against brute force, analytic answers on a box, result layouts."""
import numpy as np
import pytest

import arbor
from conftest import box_mesh, random_rays

STRUCTURES = ["bvh-median", "bvh-sah", "lbvh", "kdtree"]


def test_result_dtypes_follow_the_contract(box_scene):
    o = np.array([[0.1, 0.2, -5], [9, 9, -5]], np.float32)  # (0, 0) would cross the faces' diagonals
    d = np.array([[0, 0, 1], [0, 0, 1]], np.float32)
    h = box_scene.intersect(o, d)
    assert h.dtype == arbor.hit_dtype and h.shape == (2,)
    assert h.dtype.names == ("t", "geom", "prim", "u", "v")
    assert [h.dtype[n] for n in h.dtype.names] == [np.dtype("f4"), np.dtype("u4"), np.dtype("u4"), np.dtype("f4"), np.dtype("f4")]
    assert h[1]["t"] == np.inf and h[1]["geom"] == 0xFFFFFFFF and h[1]["prim"] == 0xFFFFFFFF and h[1]["u"] == 0 and h[1]["v"] == 0
    occ = box_scene.occluded(o, d)
    assert occ.dtype == np.bool_ and list(occ) == [True, False]
    hits, counts = box_scene.intersect_all(o, d, max_hits=3)
    assert hits.shape == (2, 3) and hits.dtype == arbor.hit_dtype and counts.dtype == np.int32
    assert list(counts) == [2, 0]
    np.testing.assert_allclose(hits[0]["t"][:2], [4, 6])
    assert hits[0][2]["t"] == np.inf and np.all(hits[1]["prim"] == arbor.MISS)
    res = box_scene.closest_point(np.array([[0, 0, -3], [0.5, 0.25, 0]], np.float32))
    assert res.dtype == arbor.point_dtype and res["point"].shape == (2, 3)
    assert res.dtype.names == ("distance", "geom", "prim", "point", "u", "v")
    np.testing.assert_allclose(res["distance"], [2.0, 0.5])
    np.testing.assert_allclose(res["point"], [[0, 0, -1], [1, 0.25, 0]], atol=1e-6)
    far = box_scene.closest_point([[0, 0, -3]], max_distance=1.5)
    assert far["distance"][0] == np.inf and far["prim"][0] == arbor.MISS
    ins = box_scene.inside(np.array([[0, 0, 0], [0.99, -0.99, 0.5], [1.01, 0, 0], [5, 5, 5]], np.float32))
    assert ins.dtype == np.bool_ and list(ins) == [True, True, False, False]


def test_counts_may_exceed_max_hits_and_ranges_cut_lists(box_scene):
    v, f = box_mesh()
    s = arbor.Scene(v, f)
    for k in range(1, 5):  # five nested boxes: ten crossings
        s.add_mesh(v * (1 + k), f)
    o, d = np.array([[0.01, 0.02, -20]], np.float32), np.array([[0, 0, 1]], np.float32)
    hits, counts = s.intersect_all(o, d, max_hits=4)
    assert counts[0] == 10 and np.all(np.diff(hits[0]["t"]) > 0)
    assert list(hits[0]["geom"]) == [4, 3, 2, 1]
    hits, counts = s.intersect_all(o, d, tnear=17.5, tfar=22.5, max_hits=16)
    assert counts[0] == 4 and list(hits[0]["geom"][:4]) == [1, 0, 0, 1]
    assert s.intersect_all(o, d, max_hits=0)[0].shape == (1, 0)


@pytest.mark.parametrize("structure", ["brute"] + STRUCTURES)
@pytest.mark.parametrize("lo,hi", [((-1, -1, -1), (1, 1, 1)), ((5.123457, -6.3, 7.77), (6.823457, -5.37, 9.97))])
def test_intersect_all_crosses_a_box_twice_through_diagonals_edges_and_corners(structure, lo, hi):
    # The triangle test gives a shared edge or vertex to one triangle there (docs/robustness.md).
    v, f = box_mesh(lo, hi)
    s = arbor.Scene(v, f)
    s.build(structure)
    lo, hi = v[0], v[6]
    mid = (lo + hi) / 2
    points = [lo, hi, np.array([lo[0], mid[1], lo[2]], np.float32), np.array([hi[0], lo[1], mid[2]], np.float32),
              np.array([mid[0], mid[1], lo[2]], np.float32)]
    o, d = [], []
    for p in points:
        for k in range(3):  # a power-of-two dominant component: the edge or corner lies exactly on the ray
            step = np.where(mid > p, 1.0, -1.0) * np.roll(np.array([4.0, 1.5, 0.75]), k)
            o.append(p - step)
            d.append(step)
    if lo[0] == -1:  # the face diagonal of z = -1, perpendicular
        o.append([0.25, 0.25, -5]), d.append([0, 0, 1])
    _, counts = s.intersect_all(np.array(o, np.float32), np.array(d, np.float32), max_hits=8)
    assert list(counts) == [2] * len(o)


@pytest.mark.parametrize("name", ["spot.obj", "suzanne.obj"])
def test_every_structure_matches_brute_force(models, name):
    path = next(m for m in models if m.name == name)
    s = arbor.Scene.load(path)
    o, d = random_rays(s, 3000, seed=3)
    tnear = np.where(np.arange(3000) % 4 == 0, 0.6, 0.0).astype(np.float32)
    rng = np.random.default_rng(5)
    lo, hi = s.bounds
    pts = (lo - 0.2 * (hi - lo) + rng.random((400, 3)) * 1.4 * (hi - lo)).astype(np.float32)
    s.build("brute")
    ref = s.intersect(o, d, tnear=tnear)
    ref_occ = s.occluded(o, d, tnear=tnear)
    ref_all, ref_counts = s.intersect_all(o, d, tnear=tnear, max_hits=8)
    ref_cp = s.closest_point(pts)
    ref_in = s.inside(pts)
    assert np.count_nonzero(np.isfinite(ref["t"])) > 1000 and np.count_nonzero(ref_counts > 2) > 100
    for name in STRUCTURES:
        s.build(name)
        h = s.intersect(o, d, tnear=tnear)
        both = np.isfinite(ref["t"])
        assert np.array_equal(np.isfinite(h["t"]), both), name
        np.testing.assert_allclose(h["t"][both], ref["t"][both], rtol=1e-4, err_msg=name)
        assert np.array_equal(s.occluded(o, d, tnear=tnear), ref_occ), name
        a, c = s.intersect_all(o, d, tnear=tnear, max_hits=8)
        assert np.array_equal(c, ref_counts) and a.tobytes() == ref_all.tobytes(), name
        assert s.closest_point(pts).tobytes() == ref_cp.tobytes(), name
        assert np.array_equal(s.inside(pts), ref_in), name


def test_closest_point_on_the_surface_and_at_vertices(spot):
    s = arbor.Scene.load(spot)
    s.build("bvh-sah")
    h = s.intersect(*random_rays(s, 500, seed=8))
    hit = h[np.isfinite(h["t"])]
    o, d = random_rays(s, 500, seed=8)
    keep = np.isfinite(h["t"])
    p = (o[keep] + d[keep] * hit["t"][:, None]).astype(np.float32)  # points on the surface
    res = s.closest_point(p)
    lo, hi = s.bounds
    assert np.all(res["distance"] < 1e-5 * np.linalg.norm(hi - lo))
    # The point reported is where its barycentrics say, and at the distance reported.
    np.testing.assert_allclose(np.linalg.norm(res["point"] - p, axis=1), res["distance"], atol=1e-6)


def test_nan_and_degenerate_rays_miss(box_scene):
    o = np.array([[np.nan, 0, -5], [0, 0, -5], [0, 0, -5], [0, 0, -5], [np.inf, 0, -5]], np.float32)
    d = np.array([[0, 0, 1], [0, 0, 0], [0, np.nan, 1], [0, 0, 1], [0, 0, 1]], np.float32)
    tn, tf = np.array([0, 0, 0, 5, 0], np.float32), np.array([9, 9, 9, 4, 9], np.float32)  # ray 3: tfar < tnear
    h = box_scene.intersect(o, d, tnear=tn, tfar=tf)
    assert np.all(np.isinf(h["t"])) and np.all(h["prim"] == arbor.MISS)
    assert not box_scene.occluded(o, d, tn, tf).any()
    assert np.all(box_scene.intersect_all(o, d, tn, tf)[1] == 0)
    res = box_scene.closest_point(np.array([[np.nan, 0, 0], [0, np.inf, 0]], np.float32))
    assert np.all(np.isinf(res["distance"])) and np.all(res["prim"] == arbor.MISS)
    assert not box_scene.inside(np.array([[np.nan, 0, 0]], np.float32)).any()


def test_read_rays_round_trip(tmp_path, box_scene):
    rng = np.random.default_rng(2)
    rec = rng.random((10, 8)).astype("<f4")
    path = tmp_path / "r.rays"
    path.write_bytes(b"RAYS" + (1).to_bytes(4, "little") + (10).to_bytes(8, "little") + rec.tobytes())
    o, d, tn, tf = arbor.read_rays(str(path))
    assert o.shape == (10, 3) and o.dtype == np.float32 and tn.shape == (10,)
    np.testing.assert_array_equal(o, rec[:, 0:3])
    np.testing.assert_array_equal(tn, rec[:, 3])
    np.testing.assert_array_equal(d, rec[:, 4:7])
    np.testing.assert_array_equal(tf, rec[:, 7])
    assert box_scene.intersect(o, d, tn, tf).shape == (10,)


def test_ray_records_read_in_place(tmp_path, spot):
    """read_rays gives views of one (N, 8) array of records, which intersect/occluded read in place
    (api/queries.cpp are_records); the answers equal those for separate contiguous arrays, also
    with tnear > 0 and a finite tfar (a wrong field offset would change them)."""
    scene = arbor.Scene.load(spot)
    scene.build("bvh-sah", threads=2)
    o, d = random_rays(scene, 3000, seed=4)
    rng = np.random.default_rng(5)
    tn = (rng.random(len(o)) * 0.5).astype(np.float32)
    tf = (1.0 + rng.random(len(o))).astype(np.float32)
    rec = np.concatenate([o, tn[:, None], d, tf[:, None]], axis=1).astype("<f4")
    path = tmp_path / "r.rays"
    path.write_bytes(b"RAYS" + (1).to_bytes(4, "little") + len(rec).to_bytes(8, "little") + rec.tobytes())
    ro, rd, rtn, rtf = arbor.read_rays(path)
    assert ro.base is not None and ro.base is rd.base and ro.base is rtn.base and ro.base is rtf.base
    assert ro.strides == (32, 4) and rtn.strides == (32,)
    copies = [np.ascontiguousarray(a) for a in (ro, rd, rtn, rtf)]
    a, b = scene.intersect(ro, rd, rtn, rtf), scene.intersect(*copies)
    assert np.count_nonzero(b["prim"] != 0xFFFFFFFF) > 100 and np.count_nonzero(b["prim"] == 0xFFFFFFFF) > 100
    assert a.tobytes() == b.tobytes()
    np.testing.assert_array_equal(scene.occluded(ro, rd, rtn, rtf), scene.occluded(*copies))
