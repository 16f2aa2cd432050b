"""Winding numbers, inside by method, signed distances and closed (python.md, "Added in 0.2")."""
import numpy as np
import pytest

import arbor
from conftest import box_mesh, read_obj


def solid_angle_winding(v, f, points):
    """The winding number in float64 numpy (Van Oosterom & Strackee), the module's oracle here."""
    tri = v.astype(np.float64)[f]  # (F, 3, 3)
    out = np.empty(len(points))
    for i, p in enumerate(points.astype(np.float64)):
        a, b, c = tri[:, 0] - p, tri[:, 1] - p, tri[:, 2] - p
        la, lb, lc = (np.linalg.norm(x, axis=1) for x in (a, b, c))
        det = np.einsum("ij,ij->i", a, np.cross(b, c))
        den = la * lb * lc + np.einsum("ij,ij->i", a, b) * lc + np.einsum("ij,ij->i", a, c) * lb + np.einsum("ij,ij->i", b, c) * la
        out[i] = np.sum(np.arctan2(det, den)) / (2 * np.pi)
    return out


def points_in_box(scene, n, seed):
    rng = np.random.default_rng(seed)
    lo, hi = scene.bounds
    return (lo - 0.2 * (hi - lo) + rng.random((n, 3)) * 1.4 * (hi - lo)).astype(np.float32)


def test_results_follow_the_contract(box_scene):
    p = np.array([[0, 0, 0], [2, 0, 0], [0.5, 0.25, -0.5]], np.float32)
    w = box_scene.winding_number(p)
    assert w.dtype == np.float64 and w.shape == (3,)
    np.testing.assert_allclose(w, [1, 0, 1], atol=0.05)
    np.testing.assert_allclose(box_scene.winding_number(p, exact=True), [1, 0, 1], atol=1e-12)
    for method in ("parity", "winding"):
        ins = box_scene.inside(p, method=method)
        assert ins.dtype == np.bool_ and list(ins) == [True, False, True]
        sd = box_scene.signed_distance(p, method=method)
        assert sd.dtype == np.float32 and sd.shape == (3,)
        np.testing.assert_allclose(sd, [-1, 1, -0.5], atol=1e-6)
    assert list(box_scene.inside(p)) == list(box_scene.inside(p, "parity"))
    np.testing.assert_array_equal(box_scene.signed_distance(p), box_scene.signed_distance(p, method="parity"))
    assert box_scene.closed is True


def test_exact_matches_numpy_and_fast_stays_close(spot):
    v, f = read_obj(spot)
    s = arbor.Scene(v, f)
    pts = points_in_box(s, 150, seed=4)
    oracle = solid_angle_winding(v, f, pts)
    for accel in ("brute", "bvh-sah", "lbvh", "kdtree"):
        s.build(accel)
        np.testing.assert_allclose(s.winding_number(pts, exact=True), oracle, rtol=0, atol=1e-9)
        fast = s.winding_number(pts)
        assert np.max(np.abs(fast - oracle)) < 0.05  # beta 2, first-order dipoles
        tight = s.winding_number(pts, beta=8.0)
        assert np.max(np.abs(tight - oracle)) <= np.max(np.abs(fast - oracle)) + 1e-12
        np.testing.assert_allclose(s.winding_number(pts, beta=np.inf), oracle, rtol=0, atol=1e-9)


def test_overlapping_parts_flipped_and_open_meshes():
    v, f = box_mesh()
    s = arbor.Scene(v, f)
    s.add_mesh(v + np.float32(1.0), f)  # overlaps the first box in [0, 1]^3
    p = np.array([[0.5, 0.5, 0.5], [-0.5, -0.5, -0.5], [1.5, 1.5, 1.5], [3, 3, 3]], np.float32)
    np.testing.assert_allclose(s.winding_number(p, exact=True), [2, 1, 1, 0], atol=1e-12)
    assert list(s.inside(p, method="winding")) == [True, True, True, False]
    assert list(s.inside(p, method="parity")) == [False, True, True, False]  # two surfaces crossed
    sd = s.signed_distance(p, method="winding")
    assert sd[0] < 0 and sd[3] > 0
    flipped = arbor.Scene(v, f[:, ::-1].copy())
    np.testing.assert_allclose(flipped.winding_number(p[:2], exact=True), [-1, -1], atol=1e-12)
    assert not flipped.inside(p[:2], method="winding").any()
    open_box = arbor.Scene(v, f[2:])  # one face (two triangles) missing
    assert not open_box.closed
    w = open_box.winding_number(np.zeros((1, 3), np.float32), exact=True)
    np.testing.assert_allclose(w, [5 / 6], atol=1e-12)  # five of six faces, seen from the centre
    assert open_box.inside(np.zeros((1, 3), np.float32), method="winding")[0]


def test_closed_by_vertex_numbers(models):
    v, f = box_mesh()
    assert arbor.Scene(v, f).closed
    assert arbor.Scene().closed  # no triangles: nothing is open
    soup = v[f].reshape(-1, 3)  # every triangle with its own corners: positions meet, numbers do not
    assert not arbor.Scene(soup, np.arange(len(soup)).reshape(-1, 3)).closed
    doubled = arbor.Scene(v, np.concatenate([f, f]))
    assert not doubled.closed
    by_name = {m.name: m for m in models}
    assert arbor.Scene.load(by_name["spot.obj"]).closed
    assert not arbor.Scene.load(by_name["stanford-bunny.obj"]).closed


def test_bad_arguments_raise_clear_errors(box_scene):
    p = np.zeros((2, 3), np.float32)
    with pytest.raises(ValueError, match="method"):
        box_scene.inside(p, method="ray")
    with pytest.raises(ValueError, match="method"):
        box_scene.signed_distance(p, method="Winding")
    with pytest.raises(ValueError, match="beta"):
        box_scene.winding_number(p, beta=1.0)
    with pytest.raises(ValueError, match="beta"):
        box_scene.inside(p, method="winding", beta=float("nan"))
    with pytest.raises(TypeError, match="beta"):
        box_scene.winding_number(p, beta="2")
    with pytest.raises(TypeError, match="beta"):
        box_scene.winding_number(p, beta=True)
    with pytest.raises(TypeError, match="beta"):
        box_scene.winding_number(p, beta=np.array([2.0, 3.0]))
    with pytest.raises(TypeError, match="method"):
        box_scene.inside(p, method=3)
    with pytest.raises(TypeError, match="exact"):
        box_scene.winding_number(p, exact=1)
    with pytest.raises(ValueError, match="threads"):
        box_scene.signed_distance(p, threads=-1)
    with pytest.raises(TypeError, match="threads"):
        box_scene.winding_number(p, threads=1.5)
    with pytest.raises(ValueError, match="out"):
        box_scene.winding_number(p, out=np.empty(3))
    with pytest.raises(TypeError, match="out: .*float32"):
        box_scene.signed_distance(p, out=np.empty(2, np.float64))
    with pytest.raises(ValueError, match="points"):
        box_scene.winding_number(np.zeros((2, 2), np.float32))
    w = box_scene.winding_number(np.array([[np.nan, 0, 0], [0, 0, np.inf]], np.float32))
    assert np.isnan(w).all()
    assert not box_scene.inside(np.array([[np.nan, 0, 0]], np.float32), method="winding")[0]
    assert box_scene.signed_distance(np.array([[np.nan, 0, 0]], np.float32), method="winding")[0] == np.inf


def test_shapes_and_out(box_scene):
    grid = np.zeros((2, 3, 3), np.float32)
    grid[1] += 2.0  # outside
    w = box_scene.winding_number(grid)
    assert w.shape == (2, 3)
    np.testing.assert_allclose(w, [[1] * 3, [0] * 3], atol=0.05)
    one = box_scene.winding_number(np.zeros(3, np.float32), exact=True)
    assert one.shape == () and abs(float(one) - 1) < 1e-12
    assert box_scene.inside(grid, "winding").shape == (2, 3)
    assert box_scene.signed_distance(np.zeros(3), method="winding").shape == ()
    out_w, out_b, out_d = np.full((2, 3), -7.0), np.zeros((2, 3), bool), np.zeros((2, 3), np.float32)
    assert box_scene.winding_number(grid, out=out_w) is out_w
    np.testing.assert_array_equal(out_w, w)
    assert box_scene.inside(grid, method="winding", out=out_b) is out_b
    assert out_b.tolist() == [[True] * 3, [False] * 3]
    assert box_scene.signed_distance(grid, "parity", out=out_d) is out_d
    np.testing.assert_allclose(out_d, [[-1] * 3, [np.sqrt(3)] * 3], atol=1e-6)


def test_per_call_threads_do_not_change_answers(spot):
    s = arbor.Scene.load(spot)
    s.build("bvh-sah", threads=2)
    pts = points_in_box(s, 3000, seed=7)
    for q in (lambda t: s.winding_number(pts, threads=t), lambda t: s.inside(pts, "winding", threads=t),
              lambda t: s.signed_distance(pts, "winding", threads=t), lambda t: s.inside(pts, threads=t)):
        np.testing.assert_array_equal(q(1), q(0))
        np.testing.assert_array_equal(q(1), q(2))


def test_answers_do_not_depend_on_threads(spot):
    pts = None
    answers = []
    for threads in (1, 2):
        s = arbor.Scene.load(spot)
        s.build("bvh-sah", threads=threads)
        if pts is None:
            pts = points_in_box(s, 3000, seed=6)
        answers.append((s.winding_number(pts), s.signed_distance(pts, method="winding")))
    np.testing.assert_array_equal(answers[0][0], answers[1][0])
    np.testing.assert_array_equal(answers[0][1], answers[1][1])
