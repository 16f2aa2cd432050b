#!/usr/bin/env python3
"""The fcpw peer of the peers benchmark (scripts/peers/fcpw_peer.py and fcpw_shim.cpp), checked on
a unit cube whose answers are known by hand: every query, the tnear/tfar and direction-length
mapping the shim does for fcpw's rays, and the same answers on 1 and 2 threads. It needs an fcpw
checkout (ARBOR_FCPW=DIR, as for scripts/bench_peers.py); without one it exits 77 (skipped).

  ARBOR_FCPW=/path/to/fcpw /usr/bin/python3 tests/peers_fcpw_test.py
"""
import math
import os
import pathlib
import sys

import numpy as np

fcpw_dir = os.environ.get("ARBOR_FCPW")
if not fcpw_dir:
    print("peers fcpw: skipped (no ARBOR_FCPW checkout)")
    sys.exit(77)
sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent.parent / "scripts"))
from peers import meshes, queries  # noqa: E402
from peers.fcpw_peer import FcpwPeer, compile_shim  # noqa: E402

failures = []


def check(cond, what):
    if not cond:
        failures.append(what)


def rays(rows):
    o, d, tn, tf = (np.array([r[k] for r in rows], np.float32) for k in range(4))
    return o, d, tn, tf


try:
    compile_shim("/nonexistent-fcpw")
    check(False, "a directory without fcpw's headers is refused")
except RuntimeError as e:
    check("--fcpw /nonexistent-fcpw" in str(e), f"the refusal names --fcpw and the directory ({e})")
shim = compile_shim(fcpw_dir)
v, f = meshes.unit_cube()
peer, robust = FcpwPeer(2, fcpw_dir, shim), FcpwPeer(2, fcpw_dir, shim, robust=True)
for p in (peer, robust):
    check(p.build(v, f) >= 0, f"{p.name} builds")
inf = np.inf
r = rays([
    ([0.5, 0.5, -1], [0, 0, 1], 0, inf),     # through the bottom face: t 1
    ([0.5, 0.5, -1], [0, 0, 2], 0.25, inf),  # a longer direction and a tnear: t 0.5 in its units
    ([0.5, 0.5, -1], [0, 0, 2], 0, 0.4),     # tfar before the face: a miss
    ([2, 2, 2], [1, 0, 0], 0, inf),          # past the cube
    ([0.5, 0.5, 0.5], [1, 0, 0], 0.1, inf),  # from the centre, tnear inside: t 0.5
    ([0.3, 0.6, -1], [0, 0, 1], 0, 1.5),     # tfar between the two faces
])
want_t = np.array([1, 0.5, inf, inf, 0.5, 1], np.float32)
for p in (peer, robust):
    t = p.closest(p.prepare_rays(*r))
    check(np.array_equal(np.isinf(t), np.isinf(want_t)) and np.allclose(t[np.isfinite(t)], want_t[np.isfinite(want_t)],
                                                                       rtol=1e-6), f"{p.name} closest t {t}")
check(np.array_equal(peer.any(peer.prepare_rays(*r)), np.isfinite(want_t)), "any hit where closest hits")
count = peer.count(peer.prepare_rays(*rays([([0.3, 0.6, -1], [0, 0, 1], 0, inf), ([0.3, 0.6, -1], [0, 0, 1], 0, 1.5),
                                             ([2, 2, 2], [1, 0, 0], 0, inf)])))
check(count.tolist() == [2, 1, 0], f"crossing counts 2, 1 (tfar), 0 (got {count.tolist()})")
pts = np.array([[0.5, 0.5, 2], [2, 2, 2], [0.5, 0.5, 0.5], [2, 0.5, -1]], np.float32)
dist = peer.closest_point(peer.prepare_points(pts))
check(np.allclose(dist, [1, math.sqrt(3), 0.5, math.sqrt(2)], rtol=1e-6), f"closest-point distances {dist}")
inside = peer.inside(peer.prepare_points(np.array([[0.3, 0.6, 0.4], [2, 0.5, 0.5], [0.7, 0.2, 1.3]], np.float32)))
check(inside.tolist() == [True, False, False], f"inside, outside beside, outside above (got {inside.tolist()})")
# Edge-aimed rays: the same answers on 1 and 2 threads, every call. (Whether fcpw is right on them
# is the benchmark's business, refereed there: this checks the shim, not fcpw.)
(o, d, tn, tf), _ = queries.edge_rays(v, f, 4000, 7)
for p in (peer, robust):
    one = FcpwPeer(1, fcpw_dir, shim, robust=p.robust)
    one.build(v, f)
    for q in sorted(p.offers - {"closest_point", "inside"}):
        a, b = getattr(p, q)(p.prepare_rays(o, d, tn, tf)), getattr(one, q)(one.prepare_rays(o, d, tn, tf))
        check(np.array_equal(a, b), f"{p.name} {q}: the same answers on 1 and 2 threads")
pts = queries.box_points(v, 4000, 3)
one = FcpwPeer(1, fcpw_dir, shim)
one.build(v, f)
for q in ("closest_point", "inside"):
    check(np.array_equal(getattr(peer, q)(pts), getattr(one, q)(pts)), f"fcpw {q}: the same answers on 1 and 2 threads")
print(f"peers fcpw ({peer.describe()})")
if failures:
    print("FAIL:\n  " + "\n  ".join(failures))
    sys.exit(1)
print("peers fcpw: all checks passed")
