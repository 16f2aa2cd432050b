#!/usr/bin/env python3
"""Render time and rays per second per integrator, median of repeated runs, as a Markdown table.

    scripts/bench_render.py [--arbor BIN] [--scene SCENE] [--width W] [--height H] [--spp N]
                            [--threads N] [--repeat K] [--integrators primary,ao,direct,path]
                            [-- extra arbor render options]

Runs `arbor render SCENE --integrator I ...` K times per integrator, the integrators interleaved
(round r renders every integrator once) so that a change of machine load hits all of them alike,
and prints one row per integrator: median render seconds (min-max), median rays per second overall
and per kind (rays / (time inside the structure / threads)), the process CPU time (user + system,
which includes the structure's build and the EXR write) and rays per CPU second (less sensitive
to other jobs on a shared machine than the wall time), rays per pixel, and the load average
before and after. The EXR goes to a temporary folder; the PNG is not written.
"""
import argparse
import os
import re
import resource
import statistics
import subprocess
import sys
import tempfile

RENDER = re.compile(r"rendered in ([0-9.]+) s with (\d+) threads")
OVERALL = re.compile(r"^rays: ([0-9.e+]+) Mrays/s overall \(([0-9.e+]+) rays in")
KIND = re.compile(r"; (\w+) ([0-9.e+]+) at ([0-9.e+]+) Mrays/s")
PLAN = re.compile(r"^plan: .*$", re.M)


def load():
    with open("/proc/loadavg") as f:
        return " ".join(f.read().split()[:3])


def child_cpu():
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def run(cmd):
    cpu0 = child_cpu()
    p = subprocess.run(cmd, capture_output=True, text=True)
    cpu = child_cpu() - cpu0
    if p.returncode != 0:
        sys.exit(f"{' '.join(cmd)}: exit {p.returncode}: {p.stderr.strip()}")
    out = p.stdout
    seconds = float(RENDER.search(out).group(1))
    rays_line = next(l for l in out.splitlines() if l.startswith("rays: "))
    m = OVERALL.match(rays_line)
    kinds = {k: (float(n), float(r)) for k, n, r in KIND.findall(rays_line)}
    return seconds, float(m.group(1)), float(m.group(2)), kinds, PLAN.search(out).group(0), cpu


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    ap.add_argument("--arbor", default=os.path.join(root, "build/release/apps/arbor/arbor"))
    ap.add_argument("--scene", default=os.path.join(root, "../shared/scenes/models/stanford-bunny.obj"))
    ap.add_argument("--width", type=int, default=1024)
    ap.add_argument("--height", type=int, default=1024)
    ap.add_argument("--spp", type=int, default=4)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--integrators", default="primary,ao,direct,path")
    ap.add_argument("extra", nargs="*", help="more arbor render options (after --)")
    a = ap.parse_args()
    integrators = a.integrators.split(",")
    results = {i: [] for i in integrators}
    plans = {}
    load_before = load()
    with tempfile.TemporaryDirectory() as tmp:
        for r in range(a.repeat):
            for i in integrators:
                cmd = [a.arbor, "render", a.scene, "-q", "--no-png", "-o", os.path.join(tmp, "out.exr"),
                       "--width", str(a.width), "--height", str(a.height), "--spp", str(a.spp),
                       "--threads", str(a.threads), "--integrator", i] + a.extra
                s, mrays, rays, kinds, plan, cpu = run(cmd)
                results[i].append((s, mrays, rays, kinds, cpu))
                plans[i] = plan
                print(f"round {r + 1}/{a.repeat} {i}: {s:.3f} s, {mrays:.3g} Mrays/s", file=sys.stderr)
    load_after = load()
    pixels = a.width * a.height
    print(f"scene {os.path.basename(a.scene)}, {a.width}x{a.height}, {a.spp} spp, {a.threads} threads, "
          f"median of {a.repeat} interleaved runs; load average before {load_before}, after {load_after}\n")
    print("| integrator | render s (min-max) | process CPU s | Mrays/s overall | Mrays per CPU-s | rays/pixel |"
          " rays per kind: Mrays/s in the structure |")
    print("|---|---|---|---|---|---|---|")
    for i in integrators:
        runs = results[i]
        secs = [x[0] for x in runs]
        med = statistics.median(secs)
        mrays = statistics.median(x[1] for x in runs)
        rays = runs[0][2]
        per_kind = []
        for k in runs[0][3]:
            rates = [x[3][k][1] for x in runs if k in x[3]]
            per_kind.append(f"{k} {runs[0][3][k][0] / 1e6:.3g}M at {statistics.median(rates):.3g}")
        cpu = statistics.median(x[4] for x in runs)
        print(f"| {i} | {med:.3f} ({min(secs):.3f}-{max(secs):.3f}) | {cpu:.2f} | {mrays:.3g} | "
              f"{rays / 1e6 / cpu:.3g} | {rays / pixels:.2f} | "
              f"{'; '.join(per_kind)} |")
    print()
    for i in integrators:
        print(f"- {i}: `{plans[i]}`")
    return 0


if __name__ == "__main__":
    sys.exit(main())
