#!/usr/bin/env python3
"""The peers benchmark's referee and edge rays (scripts/peers/), checked on a unit cube whose
answers are known by hand, and arbor checked against the referee on the cube's edge-aimed rays.

  PYTHONPATH=build/release/python python3 tests/peers_referee_test.py
"""
import math
import pathlib
import sys

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent.parent / "scripts"))
import arbor  # noqa: E402
from peers import meshes, queries  # noqa: E402
from peers.compare import agree  # noqa: E402
from peers.referee import Referee  # noqa: E402

failures = []


def check(cond, what):
    if not cond:
        failures.append(what)


v, f = meshes.unit_cube()
ref = Referee(v, f)
# Rays: through a face's middle, out the other side; a miss; a ray from inside.
check(ref.closest_t([0.5, 0.5, -1], [0, 0, 1], 0, np.inf) == 1.0, "closest t through the bottom face")
check(ref.crossings([0.3, 0.6, -1], [0, 0, 1], 0, np.inf) == 2, "two crossings through the cube")
check(math.isinf(ref.closest_t([2, 2, 2], [1, 0, 0], 0, np.inf)), "a ray past the cube misses")
check(ref.closest_t([0.5, 0.5, 0.5], [1, 0, 0], 0, np.inf) == 0.5, "from the centre to a face")
check(ref.crossings([0.3, 0.6, -1], [0, 0, 1], 0, 1.5) == 1, "tfar cuts the second crossing")
# Distances: above a face, beyond a corner, the centre.
check(abs(ref.distance([0.5, 0.5, 2]) - 1) < 1e-12, "distance above a face")
check(abs(ref.distance([2, 2, 2]) - math.sqrt(3)) < 1e-12, "distance beyond a corner")
check(abs(ref.distance([0.5, 0.5, 0.5]) - 0.5) < 1e-12, "distance from the centre")
check(abs(ref.distance([2, 0.5, -1]) - math.sqrt(2)) < 1e-12, "distance beyond an edge")
# Winding numbers: 1 inside, 0 outside, flipped faces give -1.
check(abs(ref.winding([0.3, 0.6, 0.5]) - 1) < 1e-12, "winding number inside")
check(abs(ref.winding([2, 0.5, 0.5])) < 1e-12, "winding number outside")
check(abs(Referee(v, f[:, ::-1].copy()).winding([0.5, 0.5, 0.5]) + 1) < 1e-12, "flipped faces wind -1")
# Edges: 12 cube edges and 6 face diagonals, each shared by two faces; the cube is closed.
e, third = meshes.interior_edges(f)
check(len(e) == 18 and third.shape == (18, 2), f"18 interior edges (got {len(e)})")
check(meshes.is_closed(f) and not meshes.is_closed(f[:-1]), "closed, and open with a face removed")
# Edge-aimed rays: those that pierce hit at the aimed point (t = 1) at the latest; those that graze
# a cube edge exist (a convex solid has outlines from every side).
(o, d, tn, tf), grazing = queries.edge_rays(v, f, 2000, 7)
check(0 < grazing.sum() < 2000, f"some rays graze, some pierce (grazing: {grazing.sum()})")
t_ref = np.array([ref.closest_t(o[i], d[i], tn[i], tf[i]) for i in range(2000)])
check(np.all(t_ref[~grazing] <= 1 + 1e-6), "every piercing ray hits at the aimed point or before")
# arbor against the referee on the piercing rays, every structure.
scene = arbor.Scene(v, f)
for accel in ("brute", "bvh-sah", "lbvh", "kdtree"):
    scene.build(accel=accel, threads=2)
    t = scene.intersect(o, d, tn, tf)["t"]
    scale = meshes.diagonal(v) / np.linalg.norm(d.astype(np.float64), axis=1)
    ok = agree("closest", t[~grazing], t_ref[~grazing], scale[~grazing])
    check(ok.all(), f"arbor {accel} agrees with the referee on every piercing edge ray ({(~ok).sum()} differ)")
# The comparison itself: a miss against a hit, and t off by more than its tolerance, disagree.
check(not agree("closest", np.array([np.inf]), np.array([1.0]), np.array([1.0]))[0], "a miss is not a hit")
check(not agree("closest", np.array([1.001]), np.array([1.0]), np.array([1.0]))[0], "t off by 1e-3 differs")
check(agree("closest", np.array([1.00001]), np.array([1.0]), np.array([1.0]))[0], "t off by 1e-5 agrees")

if failures:
    print("FAIL:\n  " + "\n  ".join(failures))
    sys.exit(1)
print("peers referee: all checks passed")
