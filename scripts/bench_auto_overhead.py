#!/usr/bin/python3
"""What `--accel auto` costs on a small job: a 1,000-ray trace of a 100,000-triangle mesh.

usage: scripts/bench_auto_overhead.py [--rounds 11] [--rays 1000] [--kind primary] [--dir build/auto-overhead]

Writes a deterministic 100,000-triangle mesh (a bumpy torus, 250 x 200 quads) and `--rays` rays
(`arbor rays`, seed 5) into --dir, then runs `arbor trace --json --hits` as fresh processes,
round-robin per round: --accel auto, the default (bvh-sah) twice (the noise floor: the same
choice measured twice), and every other structure once. Reports medians over the rounds of the
process wall clock (what a user waits for: loading, auto, build, trace, writing), and auto's own
work (`auto_own_ms`: shapes, model, probe timings; the build it hands over is not its cost) as a
share of the auto process's wall time and of its build + trace. Accuracy: the .hits files of all
choices must be byte-identical (closest hits: t, prim, u, v) or the script fails.
"""
import argparse
import filecmp
import json
import math
import os
import statistics
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)


def write_mesh(path, u=250, v=200):
    """u x v quads on a torus with a smooth bump (2 u v triangles); deterministic."""
    with open(path + ".tmp", "w") as f:
        for i in range(u):
            for j in range(v):
                a, b = 2 * math.pi * i / u, 2 * math.pi * j / v
                r = 0.35 * (1 + 0.08 * math.sin(7 * a) * math.cos(5 * b) + 0.01 * math.sin(97 * a + 31 * b))
                f.write("v %.6f %.6f %.6f\n" % ((1 + r * math.cos(b)) * math.cos(a), r * math.sin(b),
                                               (1 + r * math.cos(b)) * math.sin(a)))
        p = lambda x, y: (x % u) * v + (y % v) + 1
        for i in range(u):
            for j in range(v):
                f.write("f %d %d %d\nf %d %d %d\n" % (p(i, j), p(i + 1, j), p(i + 1, j + 1), p(i, j), p(i + 1, j + 1), p(i, j + 1)))
    os.replace(path + ".tmp", path)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--rounds", type=int, default=11)
    ap.add_argument("--rays", type=int, default=1000)
    ap.add_argument("--kind", default="primary")
    ap.add_argument("--dir", default=os.path.join(ROOT, "build", "auto-overhead"))
    ap.add_argument("--arbor", default=os.path.join(ROOT, "build", "release", "apps", "arbor", "arbor"))
    a = ap.parse_args()
    os.makedirs(a.dir, exist_ok=True)
    mesh, rays = os.path.join(a.dir, "torus100k.obj"), os.path.join(a.dir, "%s%d.rays" % (a.kind, a.rays))
    if not os.path.exists(mesh):
        write_mesh(mesh)
    subprocess.run([a.arbor, "rays", "--scene", mesh, "--kind", a.kind, "--count", str(a.rays), "--seed", "5", "-o", rays],
                   check=True, stdout=subprocess.DEVNULL)
    slots = ["auto", "bvh-sah", "bvh-median", "lbvh", "kdtree", "bvh-sah#2"]
    wall, runs = {s: [] for s in slots}, {s: [] for s in slots}
    for r in range(a.rounds):
        order = slots[r % len(slots):] + slots[:r % len(slots)]  # rotate: no slot always first
        for s in order:
            hits = os.path.join(a.dir, s.replace("#", "") + ".hits")
            t0 = time.perf_counter()
            out = subprocess.run([a.arbor, "trace", "--scene", mesh, "--rays", rays, "--accel", s.split("#")[0],
                                  "--json", "--hits", hits], check=True, capture_output=True, text=True).stdout
            wall[s].append((time.perf_counter() - t0) * 1e3)
            runs[s].append(json.loads(out))
    ref = os.path.join(a.dir, "bvh-sah.hits")
    same = all(filecmp.cmp(ref, os.path.join(a.dir, s.replace("#", "") + ".hits"), shallow=False) for s in slots)
    med = lambda xs: statistics.median(xs)
    au = runs["auto"]
    own = [j["auto_own_ms"] for j in au]
    job = [j["build_ms"] + j["trace_ms"] for j in au]
    print("# --accel auto on a %d-ray %s trace of a 100,000-triangle mesh (%d rounds, medians)\n" % (a.rays, a.kind, a.rounds))
    print("| choice | process wall ms | build ms | trace ms | picked (count) |")
    print("|---|---|---|---|---|")
    for s in slots:
        picks = {}
        for j in runs[s]:
            picks[j["accel"] + "/" + j["path"]] = picks.get(j["accel"] + "/" + j["path"], 0) + 1
        print("| %s | %.1f | %.2f | %.3f | %s |" % (s, med(wall[s]), med([j["build_ms"] for j in runs[s]]),
                                                 med([j["trace_ms"] for j in runs[s]]),
                                                 ", ".join("%s (%d)" % kv for kv in sorted(picks.items()))))
    best = min((s for s in slots if s != "auto"), key=lambda s: med(wall[s]))
    print("\n- auto's own work (auto_own_ms): median %.2f ms (max %.2f) = %.2f%% of the auto process's wall clock, "
          "%.1f%% of its build + trace (%.1f ms); probed in %d of %d runs"
          % (med(own), max(own), 100 * med(own) / med(wall["auto"]), 100 * med(own) / med(job), med(job),
             sum(j["auto_probed"] for j in au), len(au)))
    print("- process wall clock: auto / default (bvh-sah) = %.3f, auto / best fixed (%s) = %.3f; "
          "noise floor: bvh-sah / bvh-sah#2 = %.3f"
          % (med(wall["auto"]) / med(wall["bvh-sah"]), best, med(wall["auto"]) / med(wall[best]),
             med(wall["bvh-sah"]) / med(wall["bvh-sah#2"])))
    print("- accuracy: the .hits files of all %d choices are %s" % (len(slots), "byte-identical" if same else "DIFFERENT"))
    print("- one reason: `%s`" % au[len(au) // 2]["auto_reason"])
    print("- load average after: %s" % open("/proc/loadavg").read().strip())
    return 0 if same else 1


if __name__ == "__main__":
    sys.exit(main())
