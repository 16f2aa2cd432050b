#!/usr/bin/python3
"""Compact mode against the default layout of the same bvh-sah tree (docs/benchmarks.md, "Compact mode").

usage: scripts/bench_compact.py [--rounds 5] [--rays 262144] [--threads 1] [--dir build/compact-bench]
                                [--scenes stanford-bunny builtin:scaling:3 woody alligator] [-o OUT.md]

Per scene and ray kind (primary, random, shadow: `arbor rays`, seed 1; shadow rays traced with
--occluded), each round runs `arbor trace --repeat 3 --json --hits` as fresh processes, the default
layout and `--compact`, the order swapped every round. Reports per set the median Mrays/s of each
layout (min-max over the rounds), the median of the rounds' compact / default ratios, whether the
two layouts' .hits files are byte-identical in every round (closest hits: t, prim, u, v; any hits:
hit or miss), and both layouts' bytes per triangle. The script fails if the hits differ.
"""
import argparse
import json
import os
import statistics
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
from ab_trace import compare_hits  # noqa: E402  (closest hits by the whole record, any hits by hit or miss)
KINDS = ("primary", "random", "shadow")


def scene_arg(name, models):
    return name if name.startswith("builtin:") else os.path.join(models, name + ".obj")


def trace(arbor, scene, rays, hits, kind, threads, compact):
    cmd = [arbor, "trace", "--scene", scene, "--rays", rays, "--hits", hits, "--accel", "bvh-sah",
           "--threads", str(threads), "--repeat", "3", "--json"]
    if kind == "shadow":
        cmd.append("--occluded")
    if compact:
        cmd.append("--compact")
    return json.loads(subprocess.run(cmd, check=True, capture_output=True, text=True).stdout)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--rays", type=int, default=262144)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--dir", default=os.path.join(ROOT, "build", "compact-bench"))
    ap.add_argument("--models", default=os.environ.get("ARBOR_MODELS", os.path.join(ROOT, "..", "shared", "scenes", "models")))
    ap.add_argument("--scenes", nargs="+", default=["stanford-bunny", "builtin:scaling:3", "woody", "alligator"])
    ap.add_argument("--arbor", default=os.path.join(ROOT, "build", "release", "apps", "arbor", "arbor"))
    ap.add_argument("-o", "--out", help="also write the report here")
    a = ap.parse_args()
    if a.rounds < 1:
        sys.exit("bench_compact.py: --rounds must be at least 1")
    os.makedirs(a.dir, exist_ok=True)
    with open("/proc/loadavg") as f:
        load_before = f.read().strip()
    rows, failed = [], False
    for name in a.scenes:
        scene = scene_arg(name, a.models)
        tag = name.replace(":", "-")
        for kind in KINDS:
            rays = os.path.join(a.dir, "%s-%s.rays" % (tag, kind))
            subprocess.run([a.arbor, "rays", "--scene", scene, "--kind", kind, "--count", str(a.rays), "--seed", "1",
                            "-o", rays], check=True, capture_output=True)
            rate = {False: [], True: []}
            ratios, same, paths, bpt, hit_count = [], True, {}, {}, None
            for r in range(a.rounds):
                got = {}
                for compact in ((False, True) if r % 2 == 0 else (True, False)):
                    hits = os.path.join(a.dir, "%s-%s-%s.hits" % (tag, kind, "compact" if compact else "default"))
                    d = trace(a.arbor, scene, rays, hits, kind, a.threads, compact)
                    got[compact] = d["mrays_per_s"]
                    rate[compact].append(d["mrays_per_s"])
                    paths[compact] = d["path"]
                    bpt[compact] = d["bytes_per_triangle"]
                    hit_count = d["hits"]
                ratios.append(got[True] / got[False])
                d_hits = os.path.join(a.dir, "%s-%s-default.hits" % (tag, kind))
                c_hits = os.path.join(a.dir, "%s-%s-compact.hits" % (tag, kind))
                rays_compared, differing = compare_hits(d_hits, c_hits, kind == "shadow")
                same = same and rays_compared >= 0 and differing == 0
            failed = failed or not same
            rows.append("| %s | %s | %.2f (%s; %.2f-%.2f) | %.2f (%s; %.2f-%.2f) | %.2f (%.2f-%.2f) | %s (%d) | %.1f; %.1f |" % (
                name, kind, statistics.median(rate[False]), paths[False], min(rate[False]), max(rate[False]),
                statistics.median(rate[True]), paths[True], min(rate[True]), max(rate[True]),
                statistics.median(ratios), min(ratios), max(ratios), same, hit_count, bpt[False], bpt[True]))
            print(rows[-1], flush=True)
    with open("/proc/loadavg") as f:
        load_after = f.read().strip()
    git = subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"], capture_output=True, text=True).stdout.strip()
    head = ["# Compact mode against the default layout", "",
            "- %d rounds, %d rays, %d thread(s), a fresh process per run (`--repeat 3`), order swapped every round; git %s" % (
                a.rounds, a.rays, a.threads, git),
            "- load average before %s, after %s" % (load_before, load_after),
            "- command: `scripts/bench_compact.py --rounds %d --rays %d --threads %d --scenes %s`" % (
                a.rounds, a.rays, a.threads, " ".join(a.scenes)), "",
            "| scene | rays | default Mrays/s (path; min-max) | compact Mrays/s (path; min-max) | compact / default (median of per-round ratios; min-max) | hits equal | bytes/tri default; compact |",
            "|---|---|---:|---:|---:|---|---:|"]
    report = "\n".join(head + rows) + "\n"
    if a.out:
        tmp = a.out + ".tmp"
        with open(tmp, "w") as f:
            f.write(report)
        os.replace(tmp, a.out)
    print(report)
    if failed:
        sys.exit("bench_compact.py: the default and compact layouts' hits differ")


if __name__ == "__main__":
    main()
