#!/usr/bin/python3
"""Per-budget summary of arbor-bench's `--accel auto` rows, for comparing runs (A/B of two builds).

usage: scripts/bench_auto_ab.py [--misses] RUN/bench.json[.gz] [...]
       scripts/bench_auto_ab.py --picks-on JUDGE/bench.json[.gz] [...] -- RUN/bench.json[.gz] [...]

For each file and ray budget: rows within 10% of the best fixed (structure, path) by the wall clock
with auto's own work counted, rows worse than 1.5x, the worst ratio, auto's summed job time over
always-the-default's (bvh-sah, best path) and over the best fixed choices'; beside them the noise
floors of that run (the best fixed choice measured twice, even against odd repeats, within 10%; an
oracle picking on half of the repeats, judged on the other half), then the CPU-time figures
(labelled: an idle machine's totals), how many rows probed and auto's median wall time.
--misses lists every row more than 10% over the best by the wall clock: its ratios by the wall
clock and by CPU time and without auto's own time, whether the best fixed choice measured twice
agreed within 10% (the row's own noise), the pick and the best, and auto's reason.
--picks-on judges each RUN's picks (structure and path per row) on the fixed rows of other runs,
JUDGE (e.g. a quiet machine's): by the wall clock, the pick's build + budget x its trace time
(medians) against the best fixed choice there, auto's own time left out. Picks made in two runs
judged on the same rows show what the decisions differ by, without the judging run's noise.
"""
import gzip
import json
import sys


def misses(rows):
    for a in sorted(rows, key=lambda a: -a["regret"]):
        if a["regret"] <= 0.1:
            continue
        print("    %-15s %-7s t%d %4gM  wall %.2fx cpu %.2fx without auto %.2fx%s  %s/%s, best %s/%s%s"
              % (a["scene"], a["kind"], a["threads"], a["budget"] / 1e6, 1 + a["regret"], 1 + a["regret_cpu"],
                 1 + a["regret_without_auto"], "" if a["same_twice"] else " (noisy row)", a["picked"],
                 a["picked_path"], a["best"], a["best_path"], " probed" if a["probed"] > 0 else ""))
        print("        " + a["reason"])


def read(f):
    return json.load(gzip.open(f, "rt") if f.endswith(".gz") else open(f))


def picks_on(judges, runs):
    def totals(data):
        t = {}
        for r in data["rows"]:
            if r["embree"]:
                continue
            for b, total in zip(data["meta"]["budgets"], r["total_ms"]):
                key = (r["scene"], r["kind"], r["threads"], b)
                t.setdefault(key, {})[(r["structure"], r["path"])] = total
                if r["best_path"]:
                    t[key][(r["structure"], "best")] = total
        return t
    tables = [(j, totals(read(j))) for j in judges]
    for f in runs:
        picks = [(a["scene"], a["kind"], a["threads"], a["budget"], a["picked"], a["picked_path"]) for a in read(f)["auto"]]
        out = []
        for j, t in tables:
            within = over = 0
            for *key, s, p in picks:
                row = t[tuple(key)]
                ratio = row[(s, p)] / min(row.values())
                within += ratio <= 1.10
                over += ratio > 1.5
            out.append("%.1f%% (%d > 1.5x)" % (100.0 * within / len(picks), over))
        print("%s picks, within 10%% on each judge: %s" % (f, ", ".join(out)))


def main():
    if "--picks-on" in sys.argv[1:]:
        args = sys.argv[sys.argv.index("--picks-on") + 1:]
        return picks_on(args[:args.index("--")], args[args.index("--") + 1:])
    show_misses = "--misses" in sys.argv[1:]
    for f in [a for a in sys.argv[1:] if a != "--misses"]:
        rows = read(f)["auto"]
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
        if show_misses:
            misses(rows)


if __name__ == "__main__":
    main()
