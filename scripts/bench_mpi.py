#!/usr/bin/python3
"""What `mpirun -np N arbor render` costs and gains on one machine, and the inputs of the scaling
model in the README (section Across machines). Prints Markdown; perf/results/mpi-*.md holds runs.

  scripts/bench_mpi.py [--arbor build/release/apps/arbor/arbor] [--rounds 7] [--skip-model]

1. The cost of MPI itself, on one frame: a plain process with 2 threads, mpirun -np 1 with 2
   threads, 2 ranks x 1 thread, and 2 ranks x 1 thread with rank 0 only handing out tiles;
   interleaved (the order rotates every round), wall clock of the whole job (fresh processes,
   mpirun's start, scene load and build on every rank) and the render time arbor reports.
2. N = 1, 2, 4, 8 ranks (--oversubscribe on this 2-core machine): the image equals the plain one
   byte for byte; times shown, not meaningful beyond 2 ranks.
3. Model inputs: load + build of builtin:scaling:6 (2.5M triangles), the time of one 16x16 tile at
   64 spp path traced on it, and what rank 0 takes in per second when tiles cost nothing.
"""
import argparse
import os
import re
import statistics
import subprocess
import tempfile
import time

ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
MPIRUN = ["timeout", "600", "mpirun", "--oversubscribe"]


def run(cmd, env=None):
    t0 = time.perf_counter()
    p = subprocess.run(cmd, capture_output=True, text=True, env=env or ENV)
    wall = time.perf_counter() - t0
    if p.returncode != 0:
        raise SystemExit(f"failed ({p.returncode}): {' '.join(cmd)}\n{p.stderr}")
    m = re.search(r"rendered in ([0-9.]+) s", p.stdout)
    b = re.search(r"built in ([0-9.]+) ms", p.stdout)
    return wall, float(m.group(1)) if m else float("nan"), float(b.group(1)) if b else float("nan"), p.stdout


def med(v):
    return statistics.median(v)


def rng(v):
    return f"{min(v):.2f}-{max(v):.2f}"


def overhead(arbor, rounds, work):
    frame = ["render", "builtin:cornell", "--integrator", "path", "--width", "256", "--height", "256",
             "--spp", "32", "-q", "--no-png"]
    configs = {
        "plain, 1 process x 2 threads": [arbor] + frame + ["--threads", "2"],
        "mpirun -np 1, 2 threads": MPIRUN + ["-np", "1", "--bind-to", "none", arbor] + frame + ["--threads", "2"],
        "mpirun -np 2, 1 thread each": MPIRUN + ["-np", "2", arbor] + frame + ["--threads", "1"],
        "mpirun -np 2, 1 thread each, rank 0 idle": MPIRUN + ["-np", "2", "-x", "ARBOR_MPI_ROOT_RENDERS", arbor]
        + frame + ["--threads", "1"],
    }
    names = list(configs)
    walls = {n: [] for n in names}
    renders = {n: [] for n in names}
    for r in range(rounds):
        order = names[r % len(names):] + names[:r % len(names)]
        for n in order:
            env = dict(ENV, ARBOR_MPI_ROOT_RENDERS="0") if "idle" in n else ENV
            out = os.path.join(work, "o.exr")
            w, t, _, _ = run(configs[n] + ["-o", out], env)
            walls[n].append(w)
            renders[n].append(t)
    base_w, base_r = walls[names[0]], renders[names[0]]
    print(f"Frame: `arbor render {' '.join(frame[1:])}` (Cornell box with the bunny, 74,583 triangles), "
          f"{rounds} rounds, configurations interleaved, the order rotated each round.\n")
    print("| configuration | job wall s, median [min-max] | x plain (median of per-round ratios) "
          "| render s (arbor's), median [min-max] | x plain |")
    print("|---|---:|---:|---:|---:|")
    for n in names:
        rw = [a / b for a, b in zip(walls[n], base_w)]
        rr = [a / b for a, b in zip(renders[n], base_r)]
        print(f"| {n} | {med(walls[n]):.2f} [{rng(walls[n])}] | {med(rw):.2f} [{rng(rw)}] "
              f"| {med(renders[n]):.3f} [{rng(renders[n])}] | {med(rr):.2f} [{rng(rr)}] |")
    print()


def ranks(arbor, work):
    frame = ["render", "builtin:cornell", "--integrator", "path", "--width", "128", "--height", "96",
             "--spp", "16", "-q", "--threads", "1"]
    ref = os.path.join(work, "ref.exr")
    _, t0, _, _ = run([arbor] + frame + ["-o", ref])
    print(f"Frame: `arbor render {' '.join(frame[1:])}`; plain process: render {t0:.3f} s.\n")
    print("| ranks | job wall s | render s | image equals the plain one |")
    print("|---:|---:|---:|---|")
    for n in (1, 2, 4, 8):
        out = os.path.join(work, f"r{n}.exr")
        w, t, _, _ = run(MPIRUN + ["-np", str(n), arbor] + frame + ["-o", out])
        same = open(ref, "rb").read() == open(out, "rb").read()
        print(f"| {n} | {w:.2f} | {t:.3f} | {'yes, byte for byte' if same else 'NO'} |")
    print()


def model_inputs(arbor, work):
    out = os.path.join(work, "m.exr")
    # Load + build: a frame of one pixel, so that the rest of the job is start-up.
    w, t, b, _ = run([arbor, "render", "builtin:scaling:6", "--width", "1", "--height", "1", "--spp", "1", "-q",
                      "--no-png", "--threads", "2", "-o", out])
    w0, _, _, _ = run([arbor, "render", "--width", "1", "--height", "1", "--spp", "1", "-q", "--no-png",
                       "-o", out])
    print(f"- builtin:scaling:6: job {w:.2f} s for a 1-pixel frame, of which build {b / 1e3:.2f} s "
          f"(bvh-sah, 2 threads); a 1-pixel frame of the default scene takes {w0:.2f} s, so load "
          f"(generation) ~ {w - w0 - b / 1e3:.2f} s.")
    # One 16x16 tile at 64 spp, path: a 192x108 frame (12 x 7 = 84 tiles) on 2 threads.
    w, t, b, so = run([arbor, "render", "builtin:scaling:6", "--integrator", "path", "--width", "192",
                       "--height", "108", "--spp", "64", "-q", "--no-png", "--threads", "2", "-o", out])
    rays = re.search(r"\(([0-9.e+]+) rays in", so)
    tiles = 12 * 7
    print(f"- path, 64 spp, 192x108 (84 tiles of 16x16, the last row 12 pixels high): render {t:.2f} s on 2 "
          f"threads: {2 * t / tiles:.3f} thread-seconds per tile; {rays.group(1) if rays else '?'} rays; "
          f"`{so.splitlines()[-1]}`")
    # Rank 0's intake: a 3840x2160 frame, 1 spp, primary, of a one-triangle scene (tiles cost ~nothing).
    obj = os.path.join(work, "tri.obj")
    with open(obj, "w") as f:
        f.write("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    cheap = ["render", obj, "--integrator", "primary", "--layers", "none", "--width", "3840", "--height", "2160",
             "--spp", "1", "-q", "--no-png", "-o", out]
    rows = []
    for _ in range(3):
        _, t1, _, _ = run([arbor] + cheap + ["--threads", "1"])
        _, t2, _, _ = run(MPIRUN + ["-np", "2", "-x", "ARBOR_MPI_ROOT_RENDERS", arbor] + cheap + ["--threads", "1"],
                          dict(ENV, ARBOR_MPI_ROOT_RENDERS="0"))
        rows.append((t1, t2))
    tiles = 240 * 135
    mb = 3840 * 2160 * 3 * 4 / 1e6
    t1 = med([a for a, _ in rows])
    t2 = med([b for _, b in rows])
    print(f"- rank 0's intake: 3840x2160, 1 spp, primary, RGB only, one triangle ({tiles} tiles, {mb:.1f} MB of "
          f"pixels): one process, 1 thread: render {t1:.3f} s; 2 ranks with rank 0 only receiving: {t2:.3f} s "
          f"(median of 3) = {tiles / t2:.0f} tiles/s, {mb / t2:.0f} MB/s through rank 0 (shared memory; every "
          f"tile rendered, sent and stored).")
    print()


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--arbor", default="build/release/apps/arbor/arbor")
    ap.add_argument("--rounds", type=int, default=7)
    ap.add_argument("--skip-model", action="store_true")
    a = ap.parse_args()
    arbor = os.path.abspath(a.arbor)
    with open("/proc/loadavg") as f:
        load0 = " ".join(f.read().split()[:3])
    with tempfile.TemporaryDirectory() as work:
        print(f"## 1. The cost of MPI itself (load average at the start: {load0})\n")
        overhead(arbor, a.rounds, work)
        print("## 2. N ranks on the 2-core machine (--oversubscribe): correctness\n")
        ranks(arbor, work)
        if not a.skip_model:
            print("## 3. Model inputs\n")
            model_inputs(arbor, work)
    with open("/proc/loadavg") as f:
        print(f"Load average at the end: {' '.join(f.read().split()[:3])}")


if __name__ == "__main__":
    main()
