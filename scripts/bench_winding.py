#!/usr/bin/env python3
"""Fast winding numbers on 1M points of a ~94k-triangle closed model: time and error (docs/robustness.md).

spot.obj (5,856 triangles, closed) is subdivided twice 1-to-4 (edge midpoints shared, so it stays
closed): 93,696 triangles. 1M points uniform in its box grown by 20% are answered by
Scene.winding_number at beta 2 (and larger betas) on a bvh-sah scene built with `--threads`
threads; the first call's time includes making the dipoles, and with --repeat the median of that
many more calls is printed too, with its process CPU time (steadier than the wall time on a
shared machine). The error is measured against exact=True on a sample of the points.
Also timed: inside by parity and by winding on the same points.

    PYTHONPATH=build/release/python python3 scripts/bench_winding.py --threads 2
"""
import argparse
import os
import pathlib
import time

import numpy as np

import arbor
from peers.meshes import read_obj


def subdivide(v, f):
    """1-to-4 split at edge midpoints, one midpoint per undirected edge."""
    edges = np.sort(np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]]), axis=1)
    uniq, inv = np.unique(edges, axis=0, return_inverse=True)
    mid = len(v) + inv.reshape(3, -1).T  # midpoints of edges 01, 12, 20 per face
    v2 = np.concatenate([v, (v[uniq[:, 0]] + v[uniq[:, 1]]) / 2])
    a, b, c = f.T
    ab, bc, ca = mid.T
    f2 = np.concatenate([np.stack(t, axis=1) for t in ((a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca))])
    return v2, f2


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    shared = os.environ.get("ARBOR_SHARED_SCENES") or str(pathlib.Path(__file__).resolve().parents[1] / ".." / "shared" / "scenes")
    ap.add_argument("--model", default=str(pathlib.Path(shared) / "models" / "spot.obj"),
                    help="default: spot.obj of $ARBOR_SHARED_SCENES (else ../shared/scenes)")
    ap.add_argument("--levels", type=int, default=2, help="1-to-4 subdivisions")
    ap.add_argument("--points", type=int, default=1_000_000)
    ap.add_argument("--sample", type=int, default=2000, help="points checked against the exact sum")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--accel", default="bvh-sah")
    ap.add_argument("--betas", default="2,4,8", help="comma-separated")
    ap.add_argument("--repeat", type=int, default=0, help="time this many more calls per beta; print their median")
    ap.add_argument("--no-inside", action="store_true", help="skip the inside timings")
    ap.add_argument("--dump", help="also write the mesh, the points, the sample and its exact winding numbers "
                    "here (raw little-endian arrays, for scripts/libigl_winding.sh)")
    args = ap.parse_args()

    v, f = read_obj(args.model, np.float64)  # subdivided in double, rounded to float once
    f = f.astype(np.int64)
    for _ in range(args.levels):
        v, f = subdivide(v, f)
    scene = arbor.Scene(v.astype(np.float32), f)
    t = time.perf_counter()
    scene.build(args.accel, threads=args.threads)
    build_s = time.perf_counter() - t
    lo, hi = scene.bounds
    rng = np.random.default_rng(1)
    pts = (lo - 0.2 * (hi - lo) + rng.random((args.points, 3)) * 1.4 * (hi - lo)).astype(np.float32)
    print(f"model {pathlib.Path(args.model).name} x{4 ** args.levels}: {scene.triangles} triangles, closed {scene.closed}; "
          f"{args.accel} build {build_s:.3f} s, {args.threads} threads; {args.points} points")

    sample = pts[rng.choice(len(pts), args.sample, replace=False)]
    t = time.perf_counter()
    exact = scene.winding_number(sample, exact=True)
    exact_s = time.perf_counter() - t
    print(f"exact: {args.sample} points in {exact_s:.2f} s ({exact_s / args.sample * 1e6:.0f} us/point)")
    if args.dump:
        d = pathlib.Path(args.dump)
        d.mkdir(parents=True, exist_ok=True)
        v.astype("<f4").tofile(d / "V.f32")
        f.astype("<i4").tofile(d / "F.i32")
        pts.astype("<f4").tofile(d / "Q.f32")
        sample.astype("<f4").tofile(d / "S.f32")
        exact.astype("<f8").tofile(d / "S_exact.f64")
    print("| beta | 1M points (s) | median of repeats (s) | its cpu (s) | us/point | max abs error | 99.9th pct | mean abs error | inside wrong |")
    print("|---|---|---|---|---|---|---|---|---|")
    for beta in (float(b) for b in args.betas.split(",")):
        s = arbor.Scene(v.astype(np.float32), f)
        s.build(args.accel, threads=args.threads)
        t = time.perf_counter()
        w = s.winding_number(pts, beta=beta)  # the first call makes the dipoles
        first_s = time.perf_counter() - t
        times, cpu = [], []
        for _ in range(args.repeat):
            t, c = time.perf_counter(), time.process_time()
            s.winding_number(pts, beta=beta)
            times.append(time.perf_counter() - t)
            cpu.append(time.process_time() - c)
        median_s = float(np.median(times)) if times else float("nan")
        median_cpu = float(np.median(cpu)) if cpu else float("nan")
        err = np.abs(s.winding_number(sample, beta=beta) - exact)
        wrong = np.count_nonzero((s.winding_number(sample, beta=beta) >= 0.5) != (exact >= 0.5))
        print(f"| {beta:g} | {first_s:.3f} | {median_s:.3f} | {median_cpu:.3f} | {first_s / len(pts) * 1e6:.2f} | {err.max():.2e} | "
              f"{np.quantile(err, 0.999):.2e} | {err.mean():.2e} | {wrong} of {args.sample} |")
        del w
    if args.no_inside:
        return
    t = time.perf_counter()
    scene.inside(pts)
    parity_s = time.perf_counter() - t
    t = time.perf_counter()
    scene.inside(pts, method="winding")
    wind_s = time.perf_counter() - t
    print(f"inside, 1M points: parity {parity_s:.2f} s, winding (beta 2, dipoles made) {wind_s:.2f} s")


if __name__ == "__main__":
    main()
