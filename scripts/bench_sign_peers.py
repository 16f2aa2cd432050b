#!/usr/bin/python3
"""Signed distance and inside/outside beside Open3D, on closed meshes and on copies opened by
deleting faces: arbor's inside and signed_distance by crossing parity and by winding number,
Open3D's RaycastingScene.compute_occupancy and compute_signed_distance (Debian python3-open3d).
docs/robustness.md ("Signed distance and inside beside Open3D") shows the current table.

  /usr/bin/python3 scripts/bench_sign_peers.py [--python-path build/release/python]
      [--models ../shared/scenes/models] [--scenes cheburashka,cow,rocker-arm,spot]
      [--open 0,1,5,20] [--points 100000] [--sample 400] [--rounds 3] [--threads 2]
      [-o build/results/sign_peers.md]

Per model (closed ones: the truth is defined there) and per share of faces deleted (0: the closed
mesh; the same random faces for every library), every call answers --points points uniform in the
box grown by 10 % (scripts/peers/queries.py), with --threads threads; the calls are interleaved,
the order rotated each round, and a time (process CPU time and wall time) is the median over
--rounds rounds. Agreement is judged on --sample of these points farther than 1 % of the diagonal
from the closed mesh's surface: the oracle is the float64 sum of solid angles over the triangles of
the mesh as given (scripts/peers/referee.py; inside where it is >= 0.5), itself compared with the
closed original's inside, the answer a user of the opened mesh wanted. Signed distances count as
inside where negative; |distance| of the two libraries is compared on all points too.
"""
import argparse
import os
import pathlib
import statistics
import sys
import time

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parent.parent

# (library, call label): the rows of each table, in order.
CALLS = [("arbor", "inside parity"), ("arbor", "inside winding"), ("arbor", "signed_distance parity"),
         ("arbor", "signed_distance winding"), ("open3d", "compute_occupancy"),
         ("open3d", "compute_signed_distance")]


def opened(faces, percent, seed):
    """faces without a random `percent` % of them (none for 0)."""
    if percent == 0:
        return faces
    rng = np.random.default_rng(seed)
    drop = rng.choice(len(faces), int(round(len(faces) * percent / 100)), replace=False)
    return np.delete(faces, drop, axis=0)


def calls(arbor_scene, o3d_scene, threads):
    """call label -> (prepare points, answer -> inside mask, run)."""
    import open3d as o3d

    def sd_inside(d):
        return np.asarray(d) < 0

    return {
        "inside parity": (np.ascontiguousarray, np.asarray,
                          lambda p: arbor_scene.inside(p, method="parity", threads=threads)),
        "inside winding": (np.ascontiguousarray, np.asarray,
                           lambda p: arbor_scene.inside(p, method="winding", threads=threads)),
        "signed_distance parity": (np.ascontiguousarray, sd_inside,
                                   lambda p: arbor_scene.signed_distance(p, method="parity", threads=threads)),
        "signed_distance winding": (np.ascontiguousarray, sd_inside,
                                    lambda p: arbor_scene.signed_distance(p, method="winding", threads=threads)),
        "compute_occupancy": (o3d.core.Tensor, lambda a: a > 0.5,
                              lambda p: o3d_scene.compute_occupancy(p, nthreads=threads).numpy()),
        "compute_signed_distance": (o3d.core.Tensor, sd_inside,
                                    lambda p: o3d_scene.compute_signed_distance(p, nthreads=threads).numpy()),
    }


def run_case(verts, faces, points, sample, truth_closed, diag, o):
    import arbor
    from peers.open3d_peer import Open3dPeer
    from peers.referee import Referee

    scene = arbor.Scene(verts, faces)
    scene.build(accel="auto", threads=o.threads)
    peer = Open3dPeer(o.threads)
    peer.build(verts, faces)
    if not peer.check_mask(verts):
        sys.exit("bench_sign_peers: Open3D misses a ray aimed at the mesh: the ray-mask shim did not take")
    table = calls(scene, peer.scene, o.threads)
    prepared = {k: prep(points) for k, (prep, _, _) in table.items()}
    times = {k: [] for k in table}
    cpu = {k: [] for k in table}
    answers = {}
    keys = list(table)
    for r in range(o.rounds):
        for k in keys[r % len(keys):] + keys[:r % len(keys)]:
            t0, c0 = time.perf_counter(), time.process_time()
            answers[k] = table[k][2](prepared[k])
            times[k].append((time.perf_counter() - t0) * 1e3)
            cpu[k].append((time.process_time() - c0) * 1e3)
    ref = Referee(verts, faces)
    oracle = np.array([ref.winding(points[i]) >= 0.5 for i in sample])
    rows = {}
    for k, (_, to_inside, _) in table.items():
        inside = to_inside(answers[k])[sample]
        rows[k] = {"ms": statistics.median(times[k]), "cpu": statistics.median(cpu[k]),
                   "oracle": float(np.mean(inside == oracle))}
    gap = np.abs(np.abs(answers["signed_distance parity"].astype(np.float64))
                 - np.abs(answers["compute_signed_distance"].astype(np.float64)))
    return {"closed": bool(scene.closed), "triangles": len(faces), "rows": rows,
            "oracle_share": float(np.mean(oracle == truth_closed)), "max_dist_gap": float(gap.max() / diag),
            "describe": f"arbor {arbor.__version__} ({scene.accel}), {peer.describe()}"}


def write_report(results, o):
    """One row per model and share of faces deleted; per call its CPU and wall time and its share of
    sampled points agreeing with the oracle."""
    lines = ["# Signed distance and inside beside Open3D", "",
             f"{o.threads} threads, {o.points} points uniform in the box grown by 10 %, median of {o.rounds} "
             f"interleaved rounds: process CPU time / wall time in ms, then the share of {o.sample} of the "
             "points farther than 1 % of the diagonal from the surface on which the call agrees with the "
             "oracle (float64 sum of solid angles over the mesh as given, inside where >= 0.5).", "",
             f"- {results[0][2]['describe']}", "",
             "| model | deleted | " + " | ".join(f"{lib} {k}" for lib, k in CALLS) + " |",
             "|---|---|" + "---|" * len(CALLS)]
    for name, pct, res in results:
        cells = [f"{res['rows'][k]['cpu']:.0f} / {res['rows'][k]['ms']:.0f}: {100 * res['rows'][k]['oracle']:.1f} %"
                 for _, k in CALLS]
        lines.append(f"| {name} ({res['triangles']}) | {pct} % | " + " | ".join(cells) + " |")
    lines += ["", "Oracle against the closed original's inside on the same points, and the largest difference "
              "of |signed distance| between arbor (parity) and Open3D over all points, over the diagonal:", "",
              "| model | deleted | oracle = closed inside | max abs(distance) gap |", "|---|---|---|---|"]
    for name, pct, res in results:
        lines.append(f"| {name} | {pct} % | {100 * res['oracle_share']:.1f} % | {res['max_dist_gap']:.1e} |")
    pathlib.Path(o.out).parent.mkdir(parents=True, exist_ok=True)
    pathlib.Path(o.out).write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--python-path", default=str(ROOT / "build/release/python"))
    ap.add_argument("--models", default=str(ROOT.parent / "shared/scenes/models"))
    ap.add_argument("--scenes", default="cheburashka,cow,rocker-arm,spot")
    ap.add_argument("--open", default="0,1,5,20", help="percentages of faces deleted, comma-separated")
    ap.add_argument("--points", type=int, default=100_000)
    ap.add_argument("--sample", type=int, default=400)
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("-o", "--out", default=str(ROOT / "build/results/sign_peers.md"))
    o = ap.parse_args()
    if not os.path.isdir(o.models):
        sys.exit(f"bench_sign_peers: --models {o.models}: not found")
    sys.path.insert(0, o.python_path)
    sys.path.insert(0, str(ROOT / "scripts"))
    from peers.shim import open3d_with_mask_shim
    open3d_with_mask_shim("bench_sign_peers")
    import arbor
    from peers import meshes, queries
    from peers.referee import Referee

    results = []
    for name in o.scenes.split(","):
        verts, faces = meshes.read_obj(os.path.join(o.models, name + ".obj"))
        if not meshes.is_closed(faces):
            sys.exit(f"bench_sign_peers: --scenes {name}: not closed (the truth needs a closed original)")
        diag = meshes.diagonal(verts)
        points = queries.box_points(verts, o.points, 21)
        closed_scene = arbor.Scene(verts, faces)
        closed_scene.build(threads=o.threads)
        dist = closed_scene.closest_point(points)["distance"]
        far = np.flatnonzero(dist > 0.01 * diag)
        sample = np.sort(np.random.default_rng(22).choice(far, min(o.sample, len(far)), replace=False))
        ref = Referee(verts, faces)
        truth_closed = np.array([ref.winding(points[i]) >= 0.5 for i in sample])
        for pct in (int(x) for x in o.open.split(",")):
            print(f"== {name}, {pct} % of the faces deleted", flush=True)
            res = run_case(verts, opened(faces, pct, 23 + pct), points, sample, truth_closed, diag, o)
            for k, r in res["rows"].items():
                print(f"  {k:24s} {r['cpu']:8.1f} ms CPU {r['ms']:8.1f} ms  agrees with the oracle "
                      f"{100 * r['oracle']:5.1f} %", flush=True)
            results.append((name, pct, res))
    write_report(results, o)


if __name__ == "__main__":
    main()
