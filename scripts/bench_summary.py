#!/usr/bin/python3
"""The tables of a report's SUMMARY.md from arbor-bench's bench.json (docs/benchmarks.md).

usage: scripts/bench_summary.py OUT/bench.json > tables.md

Prints, at the largest thread count of the run:
- the headline table: per scene and ray kind, the best arbor structure/path (median Mrays/s) and
  its ratio to Embree's best mode and call on the same rays;
- --accel auto: the whole job by the wall clock with auto's own work counted against the best
  fixed (structure, path) choice first (within 10%, worst, sums against the default), noise
  floors, then the same by CPU time;
- builds: median build ms per structure per scene;
- lbvh against bvh-sah: build + trace totals per budget, and where they trade places.
"""
import json
import sys


def budget_name(b):
    for div, suffix in ((1e9, "G"), (1e6, "M"), (1e3, "k")):
        if b >= div:
            return f"{b / div:.0f}{suffix}"
    return f"{b:.0f}"


def fmt(v, d=2):
    return "–" if v is None else f"{v:.{d}f}"


def headline(rows, t):
    scenes, kinds = [], []
    for r in rows:
        if r["scene"] not in scenes:
            scenes.append(r["scene"])
        if r["kind"] not in kinds:
            kinds.append(r["kind"])
    print(f"### Headline ({t} threads): best arbor structure/path, Mrays/s, × Embree's best mode\n")
    print("| scene | tris | " + " | ".join(kinds) + " |")
    print("|---|---:|" + "---|" * len(kinds))
    ratios = []
    for s in scenes:
        tris = next(r["triangles"] for r in rows if r["scene"] == s)
        cells = []
        for k in kinds:
            sel = [r for r in rows if r["scene"] == s and r["kind"] == k and r["threads"] == t]
            a = [r for r in sel if not r["embree"]]
            e = [r for r in sel if r["embree"]]
            if not a:
                cells.append("")
                continue
            best = max(a, key=lambda r: r["mrays_per_s"]["median"])
            cell = f'{best["structure"]}/{best["path"]} {fmt(best["mrays_per_s"]["median"], 1)}'
            if e:
                eb = max(e, key=lambda r: r["mrays_per_s"]["median"])
                ratio = best["mrays_per_s"]["median"] / eb["mrays_per_s"]["median"]
                ratios.append((ratio, s, k))
                cell += f' (**{ratio:.2f}×** {eb["structure"]}/{eb["path"]})'
            cells.append(cell)
        print(f"| {s} | {tris} | " + " | ".join(cells) + " |")
    if ratios:
        rs = sorted(x[0] for x in ratios)
        print(f"\nRatio to Embree's best: {len(rs)} cells, min {rs[0]:.2f}×, median {rs[len(rs) // 2]:.2f}×, "
              f"max {rs[-1]:.2f}×; at or above 1×: {sum(x >= 1 for x in rs)}.\n")


def auto(data):
    """--accel auto, the figure a user feels first: the whole job by the wall clock, auto's own work
    counted, against the best fixed (structure, path) choice (perf/bench_auto.h); then the other
    measures, labelled."""
    a = data["auto"]
    if not a:
        return
    if "auto_total_ms" not in a[0]:
        print("### --accel auto\n\n(a report from before the wall-clock evaluation: see its bench.md)\n")
        return
    n = len(a)

    def pct(pred):
        return 100.0 * sum(1 for x in a if pred(x)) / n

    def ok(key, lim=0.10):
        return lambda x: x.get(key) is not None and x[key] <= lim

    reg = sorted(x["regret"] if x["regret"] is not None else 1e9 for x in a)
    regc = sorted(x["regret_cpu"] if x["regret_cpu"] is not None else 1e9 for x in a)
    both = [x for x in a if x["auto_total_ms"] is not None and x["default_ms"] is not None]
    s_auto = sum(x["auto_total_ms"] for x in both)
    s_best = sum(x["best_ms"] for x in both)
    s_def = sum(x["default_ms"] for x in both)
    over = sorted(x["auto_ms"] / x["auto_total_ms"] for x in a if x["auto_total_ms"] and x["probed"] < 0.5)
    print(f"### --accel auto on {n} (scene, kind, threads, budget) rows\n")
    print("The whole job by the wall clock, auto's own work counted: auto's time (shapes, model, probe) + its pick's "
          "build (unless the probe built it) + budget x the pick's trace time, against the best fixed "
          "(structure, path) choice, medians of interleaved repeats.\n")
    print("| measure | auto within 10% of the best | worst | noise floor: best fixed measured twice within 10% | split-half oracle within 10% |")
    print("|---|---:|---:|---:|---:|")
    print(f"| **wall clock, auto's own work counted** | **{pct(ok('regret')):.1f}%** | {1 + reg[-1]:.2f}x | "
          f"{pct(lambda x: x['same_twice']):.1f}% | {pct(ok('oracle_split_regret')):.1f}% |")
    print(f"| wall clock, the pick alone (auto's time left out) | {pct(ok('regret_without_auto')):.1f}% | | | |")
    print(f"| CPU time / threads (an idle machine's totals), auto's CPU time counted | {pct(ok('regret_cpu')):.1f}% | "
          f"{1 + regc[-1]:.2f}x | {pct(lambda x: x['same_twice_cpu']):.1f}% | {pct(ok('oracle_split_regret_cpu')):.1f}% |")
    print(f"\nSummed over the rows: auto {s_auto / 1e3:.1f} s, best fixed choices {s_best / 1e3:.1f} s, always the "
          f"default (bvh-sah, best path) {s_def / 1e3:.1f} s: auto / default = **{s_auto / s_def:.3f}**, "
          f"auto / best = {s_auto / s_best:.3f}. Worse than 1.5x the best: {sum(r > 0.5 for r in reg)} rows. "
          f"A probe ran on {pct(lambda x: x['probed'] >= 0.5):.1f}% of the rows; where none ran, auto's own time was a "
          f"median {100 * over[len(over) // 2] if over else 0:.2f}% (max {100 * over[-1] if over else 0:.2f}%) of the job. "
          f"Exact best (structure, path): {pct(lambda x: x['picked'] == x['best'] and x['picked_path'] == x['best_path']):.0f}%.\n")
    worst = sorted(a, key=lambda x: -(x["regret"] if x["regret"] is not None else 1e9))[:8]
    print("Worst rows (wall clock, auto counted):\n")
    print("| scene | kind | thr | budget | auto picked | best | regret | without auto | CPU | probe |")
    print("|---|---|---:|---:|---|---|---:|---:|---:|---:|")
    for x in worst:
        f = lambda v: "–" if v is None else f"{100 * v:.1f}%"
        print(f"| {x['scene']} | {x['kind']} | {x['threads']} | {budget_name(x['budget'])} | {x['picked']}/{x['picked_path']} | "
              f"{x['best']}/{x['best_path']} | {f(x['regret'])} | {f(x['regret_without_auto'])} | {f(x['regret_cpu'])} | "
              f"{100 * x['probed']:.0f}% |")
    print()


def builds(rows, t):
    print(f"### Builds ({t} threads, median ms; bytes per triangle)\n")
    structs = []
    for r in rows:
        if r["structure"] not in structs:
            structs.append(r["structure"])
    print("| scene | tris | " + " | ".join(structs) + " |")
    print("|---|---:|" + "---:|" * len(structs))
    seen = []
    for r in rows:
        if r["scene"] not in seen:
            seen.append(r["scene"])
    for s in seen:
        tris = next(r["triangles"] for r in rows if r["scene"] == s)
        cells = []
        for st in structs:
            b = [r for r in rows if r["scene"] == s and r["structure"] == st and r["threads"] == t]
            if not b or b[0]["build_ms"]["median"] is None:
                cells.append("")
            else:
                cells.append(f'{b[0]["build_ms"]["median"]:.0f} ({fmt(b[0]["bytes_per_triangle"], 0)})')
        print(f"| {s} | {tris} | " + " | ".join(cells) + " |")
    print()


def trade(rows, budgets, t):
    print(f"### lbvh against bvh-sah: build + trace total (s) per budget, primary rays, {t} threads (best path each)\n")
    print("| scene | tris | " + " | ".join(f"{budget_name(b)} rays" for b in budgets) + " | crossover (rays) |")
    print("|---|---:|" + "---:|" * (len(budgets) + 1))
    scenes = []
    for r in rows:
        if r["scene"] not in scenes:
            scenes.append(r["scene"])
    for s in scenes:
        sel = [r for r in rows if r["scene"] == s and r["kind"] == "primary" and r["threads"] == t and not r["embree"]]
        by = {}
        for st in ("lbvh", "bvh-sah"):
            c = [r for r in sel if r["structure"] == st]
            if not c:
                break
            best = max(c, key=lambda r: r["mrays_per_s"]["median"])
            by[st] = (best["build_ms"]["median"], 1e3 / (best["mrays_per_s"]["median"] * 1e6))  # ms, ms per ray
        if len(by) < 2:
            continue
        cells = []
        for b in budgets:
            tl = by["lbvh"][0] + b * by["lbvh"][1]
            ts = by["bvh-sah"][0] + b * by["bvh-sah"][1]
            win = "lbvh" if tl < ts else "sah"
            cells.append(f"{tl / 1e3:.2f} / {ts / 1e3:.2f} ({win})")
        db = by["bvh-sah"][0] - by["lbvh"][0]
        dt = by["lbvh"][1] - by["bvh-sah"][1]
        cross = f"{db / dt:.3g}" if db > 0 and dt > 0 else ("never (lbvh traces as fast)" if db > 0 else "–")
        tris = sel[0]["triangles"]
        print(f"| {s} | {tris} | " + " | ".join(cells) + f" | {cross} |")
    print("\nCell: lbvh / bvh-sah seconds (the smaller). Crossover: the budget above which bvh-sah's faster "
          "trace pays for its slower build.\n")


def errors(rows, notes):
    print("### Error columns (all rows, both thread counts)\n")
    print("| structure | path | disagreements with brute / sampled rays | with its scalar path / rays | rows with brute errors |")
    print("|---|---|---:|---:|---|")
    keys = []
    for r in rows:
        k = (r["structure"], r["path"])
        if k not in keys:
            keys.append(k)
    for st, p in keys:
        sel = [r for r in rows if r["structure"] == st and r["path"] == p]
        eb = sum(max(r["err_brute"], 0) for r in sel)
        nb = sum(r["brute_sample"] for r in sel)
        es = [r["err_scalar"] for r in sel if r["err_scalar"] is not None]
        ns = sum(r["validated_rays"] for r in sel if r["err_scalar"] is not None)
        where = sorted({f'{r["scene"]} {r["kind"]}' for r in sel if r["err_brute"] > 0})
        print(f"| {st} | {p} | {eb} / {nb} | {str(sum(es)) + ' / ' + str(ns) if es else '–'} | "
              f"{', '.join(where[:6]) + (' …' if len(where) > 6 else '')} |")
    print()
    if notes:
        print("Notes of the run: " + "; ".join(notes) + "\n")


def main():
    data = json.load(open(sys.argv[1]))
    rows = data["rows"]
    t = max(r["threads"] for r in rows)
    m = data["meta"]
    print(f"Run: {m['date']}, {m['seconds']:.0f} s, load average {m['load_before']} before, {m['load_after']} after; "
          f"{len(rows)} rows; {m['embree']}.\n")
    headline(rows, t)
    auto(data)
    builds(rows, t)
    trade(rows, m["budgets"], t)
    errors(rows, data.get("notes", []))


if __name__ == "__main__":
    main()
