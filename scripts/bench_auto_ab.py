#!/usr/bin/python3
"""Per-budget summary of arbor_bench's `--accel auto` rows, for comparing runs (A/B of two builds).

usage: scripts/bench_auto_ab.py RUN/bench.json[.gz] [...]

For each file and ray budget: rows within 10% of the best fixed (structure, path) by the wall clock
with auto's own work counted, rows worse than 1.5x, the worst ratio, auto's summed job time over
always-the-default's (bvh-sah, best path) and over the best fixed choices'; beside them the noise
floors of that run (the best fixed choice measured twice, even against odd repeats, within 10%; an
oracle picking on half of the repeats, judged on the other half), then the CPU-time figures
(labelled: an idle machine's totals), how many rows probed and auto's median wall time.
"""
import gzip
import json
import sys


def main():
    for f in sys.argv[1:]:
        rows = json.load(gzip.open(f, "rt") if f.endswith(".gz") else open(f))["auto"]
        print(f)
        for b in (1e6, 16e6, 256e6, None):
            r = [a for a in rows if b is None or a["budget"] == b]
            n = len(r)
            if not n:
                continue
            pct = lambda k: 100.0 * k / n
            print("  %-4s rows %3d | wall, auto counted: within 10%% %5.1f%%, >1.5x %2d, worst %.2fx, auto/default %.3f, "
                  "auto/best %.3f | noise floor: twice %5.1f%%, split oracle %5.1f%% | CPU: within 10%% %5.1f%%, "
                  ">1.5x %d, worst %.2fx | probed %d, median auto ms %.2f"
                  % ("all" if b is None else "%gM" % (b / 1e6), n, pct(sum(a["regret"] <= 0.1 for a in r)),
                     sum(a["regret"] > 0.5 for a in r), 1 + max(a["regret"] for a in r),
                     sum(a["auto_total_ms"] for a in r) / sum(a["default_ms"] for a in r),
                     sum(a["auto_total_ms"] for a in r) / sum(a["best_ms"] for a in r),
                     pct(sum(a["same_twice"] for a in r)), pct(sum(a["oracle_split_regret"] <= 0.1 for a in r)),
                     pct(sum(a["regret_cpu"] <= 0.1 for a in r)), sum(a["regret_cpu"] > 0.5 for a in r),
                     1 + max(a["regret_cpu"] for a in r), sum(a["probed"] > 0 for a in r),
                     sorted(a["auto_ms"] for a in r)[n // 2]))


if __name__ == "__main__":
    main()
