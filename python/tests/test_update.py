"""Scene.update_vertices (spec/python.md, "Added in 0.2"): after each step of a deforming model,
every query answers exactly as a scene built fresh from the new positions, whatever the mode and
structure; bad arguments raise TypeError or ValueError naming them and change nothing."""
import numpy as np
import pytest

import arbor
from conftest import random_rays
from deform import pose, read_obj


@pytest.fixture(scope="module")
def bunny(models):
    return read_obj(next(m for m in models if m.name == "stanford-bunny.obj"), np.int64)


def answers(scene, o, d, pts):
    hits = scene.intersect(o, d)
    all_hits, counts = scene.intersect_all(o, d, max_hits=6)
    return (hits.tobytes(), scene.occluded(o, d).tobytes(), all_hits.tobytes(), counts.tobytes(),
            scene.closest_point(pts).tobytes(), scene.inside(pts).tobytes())


@pytest.mark.parametrize("accel", ["bvh-sah", "lbvh", "kdtree"])
@pytest.mark.parametrize("mode", ["auto", "refit", "rebuild"])
def test_update_matches_a_fresh_scene(bunny, accel, mode):
    rest, faces = bunny
    scene = arbor.Scene(pose(rest, 0), faces)
    scene.build(accel)
    for step in (1, 2, 3):
        v = pose(rest, step)
        scene.update_vertices(0, v, mode=mode)
        assert scene.accel == accel
        assert scene.update_action in ("refit", "rebuild")
        assert scene.update_reason.startswith(scene.update_action + ": ")
        if accel == "kdtree" or mode == "rebuild":
            assert scene.update_action == "rebuild"
        elif mode == "refit":
            assert scene.update_action == "refit"
        fresh = arbor.Scene(v, faces)
        fresh.build("bvh-sah")
        o, d = random_rays(fresh, 300, seed=step)
        pts = np.random.default_rng(step).uniform(v.min(axis=0), v.max(axis=0), size=(200, 3)).astype(np.float32)
        assert answers(scene, o, d, pts) == answers(fresh, o, d, pts)
        assert np.array_equal(scene.bounds, fresh.bounds)


def test_update_auto_follows_the_rays_expected(bunny):
    rest, faces = bunny
    scene = arbor.Scene(pose(rest, 0), faces)
    scene.build("bvh-sah")
    scene.update_vertices(0, pose(rest, 0, 0.15), rays=0)
    assert scene.update_action == "refit" and "no rays expected" in scene.update_reason
    scene.update_vertices(0, pose(rest, 2, 0.15), rays=1e15)
    assert scene.update_action == "rebuild" and "more than a rebuild" in scene.update_reason
    assert scene.update_vertices(0, pose(rest, 3).astype(np.float64)) is None  # float64 converted


def test_update_bad_arguments_name_them_and_change_nothing(bunny):
    rest, faces = bunny
    v0 = pose(rest, 0)
    scene = arbor.Scene(v0, faces)
    scene.build("bvh-sah")
    o, d = random_rays(scene, 100)
    before = scene.intersect(o, d).tobytes()
    n = len(v0)
    bad_nan = v0.copy()
    bad_nan[7, 2] = np.nan
    bad_inf = v0.copy()
    bad_inf[3, 0] = -np.inf
    cases = [
        (TypeError, "geom", lambda: scene.update_vertices("0", v0)),
        (ValueError, "geom", lambda: scene.update_vertices(-1, v0)),
        (ValueError, "geom 5", lambda: scene.update_vertices(5, v0)),
        (TypeError, "vertices", lambda: scene.update_vertices(0, v0.astype(np.complex64))),
        (TypeError, "vertices", lambda: scene.update_vertices(0, "vertices")),
        (ValueError, "vertices", lambda: scene.update_vertices(0, v0[:, :2])),
        (ValueError, "vertices", lambda: scene.update_vertices(0, v0.reshape(-1))),
        (ValueError, f"vertices: expected {n}", lambda: scene.update_vertices(0, v0[:-1])),
        (ValueError, "vertices[7] is not finite", lambda: scene.update_vertices(0, bad_nan)),
        (ValueError, "vertices[3] is not finite", lambda: scene.update_vertices(0, bad_inf)),
        (TypeError, "mode", lambda: scene.update_vertices(0, v0, mode=1)),
        (ValueError, "mode 'fast'", lambda: scene.update_vertices(0, v0, mode="fast")),
        (ValueError, "rays", lambda: scene.update_vertices(0, v0, rays=-1)),
        (TypeError, "rays", lambda: scene.update_vertices(0, v0, rays="many")),
    ]
    for error, words, call in cases:
        with pytest.raises(error) as info:
            call()
        assert words in str(info.value), (words, str(info.value))
    assert scene.update_action == ""
    assert scene.intersect(o, d).tobytes() == before
