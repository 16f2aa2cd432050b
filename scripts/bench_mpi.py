#!/usr/bin/python3
"""What `mpirun -np N arbor render` costs and gains on one machine, and the inputs of the scaling
model in docs/mpi.md. Prints Markdown; perf/results/mpi.md holds the current baseline.

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
import resource
import statistics
import subprocess
import tempfile
import time

ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
MPIRUN = ["timeout", "600", "mpirun", "--oversubscribe"]


def cpu_children():
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def run(cmd, env=None, cpu=None):
    """Wall seconds of the job, arbor's render seconds, build ms, stdout; `cpu` (a list) gets the
    CPU seconds (user + sys) of the job and everything it waited for (mpirun, every rank)."""
    c0 = cpu_children()
    t0 = time.perf_counter()
    p = subprocess.run(cmd, capture_output=True, text=True, env=env or ENV)
    wall = time.perf_counter() - t0
    if cpu is not None:
        cpu.append(cpu_children() - c0)
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
    cpus = {n: [] for n in names}
    for r in range(rounds):
        order = names[r % len(names):] + names[:r % len(names)]
        for n in order:
            env = dict(ENV, ARBOR_MPI_ROOT_RENDERS="0") if "idle" in n else ENV
            out = os.path.join(work, "o.exr")
            w, t, _, _ = run(configs[n] + ["-o", out], env, cpus[n])
            walls[n].append(w)
            renders[n].append(t)
    base_w, base_r = walls[names[0]], renders[names[0]]
    print(f"Frame: `arbor render {' '.join(frame[1:])}` (Cornell box with the bunny, 74,583 triangles), "
          f"{rounds} rounds, configurations interleaved, the order rotated each round.\n")
    base_c = cpus[names[0]]
    print("| configuration | job CPU s (user+sys, all processes), median [min-max] | - plain, s (per-round "
          "differences) | job wall s, median [min-max] | x plain (per-round ratios) | render s (arbor's), "
          "median [min-max] | x plain |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    for n in names:
        dc = [a - b for a, b in zip(cpus[n], base_c)]
        rw = [a / b for a, b in zip(walls[n], base_w)]
        rr = [a / b for a, b in zip(renders[n], base_r)]
        print(f"| {n} | {med(cpus[n]):.2f} [{rng(cpus[n])}] | {med(dc):+.2f} [{rng(dc)}] "
              f"| {med(walls[n]):.2f} [{rng(walls[n])}] | {med(rw):.2f} [{rng(rw)}] "
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
    one_pixel = ["--width", "1", "--height", "1", "--spp", "1", "-q", "--no-png", "--threads", "2", "-o", out]
    # Load + build: a frame of one pixel, so that the rest of the job is start-up (CPU: this job's
    # minus the same 1-pixel job on the 10k-triangle default scene).
    c_big, c_small, ws, builds = [], [], [], []
    for _ in range(3):
        w, _, b, _ = run([arbor, "render", "builtin:scaling:6"] + one_pixel, cpu=c_big)
        run([arbor, "render"] + one_pixel, cpu=c_small)
        ws.append(w)
        builds.append(b / 1e3)
    lb = [a - b for a, b in zip(c_big, c_small)]
    print(f"- builtin:scaling:6, a 1-pixel frame, 3 rounds: job {med(ws):.2f} s wall [{rng(ws)}], "
          f"{med(c_big):.2f} s CPU [{rng(c_big)}]; build {med(builds):.2f} s wall [{rng(builds)}] (bvh-sah, SIMD "
          f"layout, 2 threads); minus the default scene's 1-pixel job ({med(c_small):.2f} s CPU): load + build of "
          f"the 2.5M triangles {med(lb):.2f} s CPU [{rng(lb)}].")
    # The cost of a pixel at 64 spp, path: two frame sizes of the same view, 3 rounds interleaved;
    # the difference of their jobs' CPU is the render of the extra pixels (load and build cancel).
    sizes = [(192, 108), (384, 216)]
    cpu = {sz: [] for sz in sizes}
    last = ""
    for _ in range(3):
        for sz in sizes:
            c = []
            _, t, _, so = run([arbor, "render", "builtin:scaling:6", "--integrator", "path", "--width", str(sz[0]),
                               "--height", str(sz[1]), "--spp", "64", "-q", "--no-png", "--threads", "2", "-o", out],
                              cpu=c)
            cpu[sz].append(c[0])
            last = so.splitlines()[-1]
    d = [b - a for a, b in zip(cpu[sizes[0]], cpu[sizes[1]])]
    extra = (sizes[1][0] * sizes[1][1] - sizes[0][0] * sizes[0][1]) * 64
    per_sample = med(d) / extra
    print(f"- path, 64 spp: job CPU for 192x108 {med(cpu[sizes[0]]):.2f} s [{rng(cpu[sizes[0]])}], for 384x216 "
          f"{med(cpu[sizes[1]]):.2f} s [{rng(cpu[sizes[1]])}] (3 rounds, interleaved); the difference, "
          f"{med(d):.2f} s [{rng(d)}], renders {extra / 64:.0f} pixels: {per_sample * 1e6:.3f} CPU us per pixel "
          f"sample, {per_sample * 256 * 64 * 1e3:.1f} CPU ms per 16x16 tile, {per_sample * 3840 * 2160 * 64:.0f} CPU s "
          f"for 3840x2160 at 64 spp. Last run: `{last}`")
    # Rank 0's intake: a 3840x2160 frame, 1 spp, primary, of a one-triangle scene (tiles cost ~nothing).
    obj = os.path.join(work, "tri.obj")
    with open(obj, "w") as f:
        f.write("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    cheap = ["render", obj, "--integrator", "primary", "--layers", "none", "--width", "3840", "--height", "2160",
             "--spp", "1", "-q", "--no-png", "-o", out, "--threads", "1"]
    t1s, t2s, c1s, c2s = [], [], [], []
    for _ in range(3):
        _, t1, _, _ = run([arbor] + cheap, cpu=c1s)
        _, t2, _, _ = run(MPIRUN + ["-np", "2", "-x", "ARBOR_MPI_ROOT_RENDERS", arbor] + cheap,
                          dict(ENV, ARBOR_MPI_ROOT_RENDERS="0"), c2s)
        t1s.append(t1)
        t2s.append(t2)
    tiles = 240 * 135
    mb = 3840 * 2160 * 3 * 4 / 1e6
    print(f"- rank 0's intake: 3840x2160, 1 spp, primary, RGB only, one triangle ({tiles} tiles, {mb:.1f} MB of "
          f"pixels), median of 3: one process, 1 thread: render {med(t1s):.2f} s, job {med(c1s):.2f} s CPU; "
          f"2 ranks, rank 1 rendering every tile and rank 0 only receiving: render {med(t2s):.2f} s "
          f"({tiles / med(t2s):.0f} tiles/s, {mb / med(t2s):.0f} MB/s through rank 0, shared memory), job "
          f"{med(c2s):.2f} s CPU: {(med(c2s) - med(c1s)) / tiles * 1e6:.0f} us of CPU per tile for MPI (both "
          f"ranks, start-up included).")
    print()


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--arbor", default="build/release/apps/arbor/arbor")
    ap.add_argument("--rounds", type=int, default=7)
    ap.add_argument("--skip-model", action="store_true")
    ap.add_argument("--only-model", action="store_true")
    a = ap.parse_args()
    arbor = os.path.abspath(a.arbor)
    with open("/proc/loadavg") as f:
        load0 = " ".join(f.read().split()[:3])
    with tempfile.TemporaryDirectory() as work:
        if not a.only_model:
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
