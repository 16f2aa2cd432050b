#!/usr/bin/python3
"""Plots of an `arbor-bench bench` run (docs/benchmarks.md).

usage: scripts/plot_bench.py RESULTS/bench.json [OUT_DIR]

Writes into OUT_DIR (default: beside the JSON):
  build_vs_triangles.png  build time against triangle count, log-log, per structure
  mrays_per_scene.png     Mrays/s per structure per scene, one panel per ray kind
  total_vs_budget.png     build + trace time against the ray budget, per structure, per scene
  error_vs_time.png       disagreements with brute (sample) and with Embree against trace time
All at the largest thread count of the run; a structure's best path is taken per cell.
"""
import json
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

COLORS = {"brute": "#999999", "bvh-median": "#1f77b4", "bvh-sah": "#2ca02c", "lbvh": "#ff7f0e",
          "kdtree": "#9467bd", "embree": "#d62728", "embree-high": "#8c564b", "embree-robust": "#e377c2"}


def color(s):
    return COLORS.get(s, None)


def best_per_structure(rows):
    """(scene, kind, structure) -> the row with the highest median Mrays/s."""
    best = {}
    for r in rows:
        key = (r["scene"], r["kind"], r["structure"])
        m = r["mrays_per_s"]["median"] or 0.0
        if key not in best or m > (best[key]["mrays_per_s"]["median"] or 0.0):
            best[key] = r
    return best


def ordered(values):
    out = []
    for v in values:
        if v not in out:
            out.append(v)
    return out


def plot_build(rows, out):
    fig, ax = plt.subplots(figsize=(7, 5))
    by_struct = {}
    for r in rows:
        b = r["build_ms"]["median"]
        if b is None or b <= 0:
            continue
        by_struct.setdefault(r["structure"], {})[(r["scene"], r["triangles"])] = b
    for s, pts in sorted(by_struct.items()):
        xs = sorted(pts.items(), key=lambda kv: kv[0][1])
        ax.plot([k[1] for k, _ in xs], [v for _, v in xs], "o", label=s, color=color(s), alpha=0.8)
        rep = [(k[1], v) for k, v in xs if k[0].startswith("replicated")]
        if len(rep) > 1:
            ax.plot([p[0] for p in rep], [p[1] for p in rep], "-", color=color(s), alpha=0.6)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("triangles")
    ax.set_ylabel("build time (ms, median)")
    ax.set_title("Build time against triangles (lines: replicated scenes)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    plt.close(fig)


def plot_mrays(rows, out):
    best = best_per_structure(rows)
    kinds = ordered(r["kind"] for r in rows)
    scenes = ordered(r["scene"] for r in rows)
    structs = ordered(r["structure"] for r in rows if not r["embree"]) + \
        ordered(r["structure"] for r in rows if r["embree"])
    fig, axes = plt.subplots(len(kinds), 1, figsize=(max(8, 0.9 * len(scenes) * max(1, len(structs)) / 3), 3.2 * len(kinds)),
                             squeeze=False)
    width = 0.8 / max(1, len(structs))
    for ax, kind in zip(axes[:, 0], kinds):
        for si, s in enumerate(structs):
            xs, ys = [], []
            for i, scene in enumerate(scenes):
                r = best.get((scene, kind, s))
                if r and r["mrays_per_s"]["median"]:
                    xs.append(i + (si - (len(structs) - 1) / 2) * width)
                    ys.append(r["mrays_per_s"]["median"])
            ax.bar(xs, ys, width=width, label=s, color=color(s))
        ax.set_xticks(range(len(scenes)))
        ax.set_xticklabels(scenes, rotation=30, ha="right", fontsize=8)
        ax.set_ylabel("Mrays/s")
        ax.set_yscale("log")
        ax.set_title(kind + " rays")
        ax.grid(True, axis="y", which="both", alpha=0.3)
    axes[0, 0].legend(fontsize=7, ncol=4)
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    plt.close(fig)


def plot_totals(rows, out):
    best = best_per_structure(rows)
    kind = "primary" if any(r["kind"] == "primary" for r in rows) else rows[0]["kind"]
    scenes = ordered(r["scene"] for r in rows)
    n = len(scenes)
    cols = min(4, n)
    nrows = int(math.ceil(n / cols))
    fig, axes = plt.subplots(nrows, cols, figsize=(4 * cols, 3.2 * nrows), squeeze=False)
    budgets = [10 ** (4 + 0.25 * i) for i in range(0, 21)]
    for idx, scene in enumerate(scenes):
        ax = axes[idx // cols][idx % cols]
        for (sc, k, s), r in sorted(best.items()):
            if sc != scene or k != kind:
                continue
            b, m = r["build_ms"]["median"], r["mrays_per_s"]["median"]
            if b is None or not m:
                continue
            ax.plot(budgets, [(b + x / (m * 1e6) * 1e3) * 1e-3 for x in budgets], label=s, color=color(s),
                    linestyle="--" if r["embree"] else "-")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_title(f"{scene} ({kind})", fontsize=9)
        ax.set_xlabel("ray budget")
        ax.set_ylabel("build + trace (s)")
        ax.grid(True, which="both", alpha=0.3)
        if idx == 0:
            ax.legend(fontsize=7)
    for idx in range(n, nrows * cols):
        axes[idx // cols][idx % cols].axis("off")
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    plt.close(fig)


def plot_errors(rows, out):
    fig, ax = plt.subplots(figsize=(7, 5))
    seen = set()
    for r in rows:
        t = r["trace_ms"]["median"]
        if not t:
            continue
        rate = r["err_brute"] / max(1, r["brute_sample"])
        s = r["structure"]
        ax.scatter([t], [rate], color=color(s), marker="s" if r["embree"] else "o", alpha=0.7,
                   label=None if s in seen else s)
        seen.add(s)
        if r["err_embree"] is not None and not r["embree"]:
            ax.scatter([t], [r["err_embree"] / max(1, r["rays"])], color=color(s), marker="x", alpha=0.5)
    ax.set_xscale("log")
    ax.set_yscale("symlog", linthresh=1e-4)
    ax.set_xlabel("trace time (ms, median)")
    ax.set_ylabel("fraction of rays disagreeing")
    ax.set_title("Error against time (o/□: vs brute sample; x: vs Embree default, all rays)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    plt.close(fig)


def main():
    if len(sys.argv) < 2:
        print(__doc__.strip(), file=sys.stderr)
        return 2
    path = sys.argv[1]
    try:
        data = json.load(open(path))
    except (OSError, ValueError) as e:
        print(f"plot_bench: {path}: {e}", file=sys.stderr)
        return 1
    rows = data.get("rows", [])
    if not rows:
        print(f"plot_bench: {path}: no rows", file=sys.stderr)
        return 1
    top = max(r["threads"] for r in rows)
    rows = [r for r in rows if r["threads"] == top]
    out = sys.argv[2] if len(sys.argv) > 2 else os.path.dirname(os.path.abspath(path))
    os.makedirs(out, exist_ok=True)
    plot_build(rows, os.path.join(out, "build_vs_triangles.png"))
    plot_mrays(rows, os.path.join(out, "mrays_per_scene.png"))
    plot_totals(rows, os.path.join(out, "total_vs_budget.png"))
    plot_errors(rows, os.path.join(out, "error_vs_time.png"))
    print(f"plot_bench: 4 plots in {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
