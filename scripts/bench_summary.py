#!/usr/bin/python3
"""The tables of a report's SUMMARY.md from arbor_bench's bench.json (perf/README.md).

usage: scripts/bench_summary.py OUT/bench.json > tables.md

Prints, at the largest thread count of the run:
- the headline table: per scene and ray kind, the best arbor structure/path (median Mrays/s) and
  its ratio to Embree's best mode and call on the same rays;
- --accel auto: hit rate (within 10% of the best total), regret, noise floors, wall clock and
  CPU time, and how many misses are the path TracePath::best took;
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
    a = data["auto"]
    if not a:
        return
    rows, budgets = data["rows"], data["meta"]["budgets"]
    n = len(a)

    def pct(key, lim=0.10):
        return 100.0 * sum(1 for x in a if x.get(key) is not None and x[key] <= lim) / n

    reg = sorted(x["regret"] if x["regret"] is not None else 1e9 for x in a)
    regc = sorted(x["regret_cpu"] if x.get("regret_cpu") is not None else 1e9 for x in a)
    path_only = struct = 0
    for x in a:
        if x.get("regret_cpu") is None or x["regret_cpu"] <= 0.10:
            continue
        bi = budgets.index(x["budget"])
        tot = {(r["structure"], r["path"]): r["total_cpu_ms"][bi] for r in rows
               if r["scene"] == x["scene"] and r["kind"] == x["kind"] and r["threads"] == x["threads"] and not r["embree"]}
        best = min(tot.values())
        mine = min(v for (s, p), v in tot.items() if s == x["picked"])
        if mine / best - 1 <= 0.10:
            path_only += 1
        else:
            struct += 1
    print(f"### --accel auto on {n} (scene, kind, threads, budget) rows\n")
    print("| measure | auto within 10% of the best total | regret median | mean | worst | noise floor |")
    print("|---|---:|---:|---:|---:|---:|")
    mean = sum(min(r, 10) for r in reg) / n
    meanc = sum(min(r, 10) for r in regc) / n
    print(f"| wall clock, medians of the repeats | **{pct('regret'):.1f}%** | {100 * reg[n // 2]:.1f}% | {100 * mean:.1f}% | "
          f"{100 * reg[-1]:.0f}% | {pct('oracle_split_regret'):.1f}% |")
    print(f"| CPU time / threads, fastest build | **{pct('regret_cpu'):.1f}%** | {100 * regc[n // 2]:.1f}% | "
          f"{100 * meanc:.1f}% | {100 * regc[-1]:.0f}% | {pct('oracle_split_regret_cpu'):.1f}% |")
    print(f"| wall clock, the pick on its fastest measured path | {pct('regret_any_path'):.1f}% | | | | |")
    if any("regret_best_path" in x for x in a):
        print(f"| wall clock, the pick on the path TracePath::best takes | {pct('regret_best_path'):.1f}% | | | | |")
    print(f"| wall clock + auto's calibration time | {pct('regret_with_overhead'):.1f}% | | | | |")
    print(f"\nBy CPU time, {path_only + struct} misses: {path_only} where auto's structure is within 10% on one of "
          f"its paths but ran another, {struct} where the structure itself is more than 10% "
          f"off. Exact best structure picked: {100.0 * sum(x['picked'] == x['best'] for x in a) / n:.0f}%.\n")


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
