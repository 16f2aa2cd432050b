#!/usr/bin/env python3
"""Process-level A/B of two `arbor` binaries on the benchmark ray files (docs/benchmarks.md: `arbor rays
--kind primary|shadow|diffuse|random --count 131072`, seed 1, tile order, of the bunny, the beast
and the rocker arm): every (file, structure, path) runs as a fresh `arbor trace` process of each
binary, interleaved (A B / B A alternating, all configurations once per round), and the hits of
the two are compared (closest hit: the whole 16-byte record; any hit, the shadow files: hit/miss,
since any hit may name another occluder).

  scripts/ab_trace.py OLD_ARBOR NEW_ARBOR RAYS_DIR [--models DIR] [--rounds 3] [--threads 1] [-o OUT.csv]
                      [--scenes A,B] [--structures A,B] [--paths A,B]   (subsets of the defaults below)
                      [--repeat K]   (each process traces K times: trace_ms is its median)

Prints per structure and path the median over files of the per-file ratio new/old of the median
wall clock (the whole process: load, build, trace, write hits), build_ms and trace_ms, and writes
every sample to OUT.csv.
"""
import argparse
import csv
import json
import os
import statistics
import struct
import subprocess
import sys
import tempfile
import time

SCENES = ["stanford-bunny", "beast", "rocker-arm"]
KINDS = ["primary", "shadow", "diffuse", "random"]
STRUCTURES = ["bvh-median", "bvh-sah", "lbvh", "kdtree"]
PATHS = ["scalar", "single", "packet", "best"]


def run(binary, scene, rays, structure, path, occluded, threads, hits, repeat=1):
    cmd = [binary, "trace", "--scene", scene, "--rays", rays, "--accel", structure, "--path", path,
           "--threads", str(threads), "--json", "--hits", hits, "--repeat", str(repeat)] + (["--occluded"] if occluded else [])
    t0 = time.perf_counter()
    out = subprocess.run(cmd, capture_output=True, text=True)
    wall = (time.perf_counter() - t0) * 1e3
    if out.returncode != 0:
        sys.exit(f"ab_trace: {' '.join(cmd)} exited {out.returncode}: {out.stderr.strip()}")
    j = json.loads(out.stdout)
    return wall, j["build_ms"], j["trace_ms"]


def compare_hits(a, b, any_hit):
    """(rays, rays differing): closest hits by the whole record, any hits by hit/miss."""
    x, y = open(a, "rb").read(), open(b, "rb").read()
    if len(x) != len(y):
        return -1, -1
    n = (len(x) - 16) // 16
    if x == y:
        return n, 0
    diff = 0
    for i in range(16, len(x), 16):
        if any_hit:
            px = struct.unpack_from("<I", x, i + 4)[0]
            py = struct.unpack_from("<I", y, i + 4)[0]
            diff += (px == 0xFFFFFFFF) != (py == 0xFFFFFFFF)
        else:
            diff += x[i:i + 16] != y[i:i + 16]
    return n, diff


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("old")
    ap.add_argument("new")
    ap.add_argument("rays")
    ap.add_argument("--models", default=os.path.join(os.path.dirname(__file__), "..", "..", "shared", "scenes", "models"))
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("-o", "--out", default="ab_trace.csv")
    ap.add_argument("--scenes", default=",".join(SCENES))
    ap.add_argument("--structures", default=",".join(STRUCTURES))
    ap.add_argument("--paths", default=",".join(PATHS))
    ap.add_argument("--repeat", type=int, default=1)
    o = ap.parse_args()
    scenes, structures, paths = o.scenes.split(","), o.structures.split(","), o.paths.split(",")
    tmp = tempfile.mkdtemp(prefix="ab_trace.")
    configs = [(s, k, st, p) for s in scenes for k in KINDS for st in structures for p in paths]
    rows, accuracy = [], {}
    for r in range(o.rounds):
        for ci, (s, k, st, p) in enumerate(configs):
            scene = os.path.join(o.models, s + ".obj")
            rays = os.path.join(o.rays, f"{s}-{k}.rays")
            order = [("old", o.old), ("new", o.new)]
            if (r + ci) % 2:
                order.reverse()
            for label, binary in order:
                hits = os.path.join(tmp, f"{label}.hits")
                wall, build, trace = run(binary, scene, rays, st, p, k == "shadow", o.threads, hits, o.repeat)
                rows.append({"round": r, "scene": s, "kind": k, "structure": st, "path": p, "binary": label,
                             "wall_ms": wall, "build_ms": build, "trace_ms": trace})
            if r == 0:
                accuracy[(s, k, st, p)] = compare_hits(os.path.join(tmp, "old.hits"), os.path.join(tmp, "new.hits"), k == "shadow")
        print(f"round {r + 1}/{o.rounds} done", file=sys.stderr, flush=True)
    with open(o.out, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)

    def med(label, cfg, field):
        return statistics.median(x[field] for x in rows if x["binary"] == label and
                                 (x["scene"], x["kind"], x["structure"], x["path"]) == cfg)

    print(f"| structure | path | wall new/old (median over {len(scenes) * len(KINDS)} files; min..max) | build_ms new/old | trace_ms new/old | rays with other hits |")
    print("|---|---|---|---|---|---|")
    for st in structures:
        for p in paths:
            cfgs = [c for c in configs if c[2] == st and c[3] == p]
            ratios = {f: [med("new", c, f) / med("old", c, f) for c in cfgs] for f in ("wall_ms", "build_ms", "trace_ms")}
            diff = sum(accuracy[c][1] for c in cfgs)
            wr = ratios["wall_ms"]
            print(f"| {st} | {p} | {statistics.median(wr):.3f} ({min(wr):.3f}..{max(wr):.3f}) | "
                  f"{statistics.median(ratios['build_ms']):.3f} | {statistics.median(ratios['trace_ms']):.3f} | {diff} |")
    allw = [med("new", c, "wall_ms") / med("old", c, "wall_ms") for c in configs]
    allt = [med("new", c, "trace_ms") / med("old", c, "trace_ms") for c in configs]
    print(f"\nall {len(configs)} configurations: wall new/old median {statistics.median(allw):.3f} "
          f"(min {min(allw):.3f}, max {max(allw):.3f}); trace_ms new/old median {statistics.median(allt):.3f} "
          f"(min {min(allt):.3f}, max {max(allt):.3f})")
    print(f"hits: {sum(1 for c in configs if accuracy[c][1] == 0)} of {len(configs)} configurations identical "
          f"(closest: whole record; shadow/any hit: hit or miss); rays differing: {sum(a[1] for a in accuracy.values())}")
    slower = sorted(((med('new', c, 'wall_ms') / med('old', c, 'wall_ms'), c) for c in configs), reverse=True)[:8]
    print("slowest ratios (wall):", ", ".join(f"{'/'.join(c)} {x:.3f}" for x, c in slower))


if __name__ == "__main__":
    main()
