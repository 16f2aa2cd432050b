#!/usr/bin/env python3
"""Plots arbor's error against run time: `plot_converge.py converge.csv converge.png [TITLE]`.

Reads the CSV written by `arbor converge` (columns accel, integrator, spp, seconds, rmse, rel_mse,
...) and draws RMSE and relative MSE against seconds on log-log axes, one line per
(structure, integrator), each point labelled with its samples per pixel. A dashed line of slope
-1/2 (RMSE) and -1 (relative MSE) shows the Monte-Carlo rate.
Exit status 3 means matplotlib is missing; 2 means the CSV could not be used.
"""
import csv
import sys


def main():
    if len(sys.argv) < 3:
        print("usage: plot_converge.py converge.csv converge.png [TITLE]", file=sys.stderr)
        return 2
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib is not installed (Debian: python3-matplotlib)", file=sys.stderr)
        return 3
    series = {}
    try:
        with open(sys.argv[1], newline="") as f:
            for row in csv.DictReader(f):
                key = (row["accel"], row.get("integrator", ""))
                series.setdefault(key, []).append(
                    (float(row["seconds"]), float(row["rmse"]), float(row["rel_mse"]), int(row["spp"])))
    except (OSError, KeyError, ValueError) as e:
        print(f"{sys.argv[1]}: cannot read ({e})", file=sys.stderr)
        return 2
    if not series:
        print(f"{sys.argv[1]}: no rows", file=sys.stderr)
        return 2
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.5))
    for ax, col, name, slope in ((axes[0], 1, "RMSE", -0.5), (axes[1], 2, "relative MSE", -1.0)):
        for (accel, integrator), pts in sorted(series.items()):
            pts = sorted((p for p in pts if p[0] > 0 and p[col] > 0), key=lambda p: p[3])  # by spp
            if not pts:
                continue
            xs, ys = [p[0] for p in pts], [p[col] for p in pts]
            label = f"{accel} / {integrator}" if integrator else accel
            ax.plot(xs, ys, marker="o", label=label)
            for p in pts:
                ax.annotate(str(p[3]), (p[0], p[col]), textcoords="offset points", xytext=(4, 4), fontsize=7)
            x0, y0 = xs[0], ys[0]
            x1 = xs[-1] if xs[-1] > x0 else x0 * 10
            ax.plot([x0, x1], [y0, y0 * (x1 / x0) ** slope], linestyle="--", color="grey", linewidth=0.8)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("render time (s)")
        ax.set_ylabel(name)
        ax.set_title(f"{name} against time (dashed: slope {slope:g})")
        ax.grid(True, which="both", linewidth=0.3)
        ax.legend(fontsize=8)
    if len(sys.argv) > 3:
        fig.suptitle(sys.argv[3])
    fig.tight_layout()
    fig.savefig(sys.argv[2], dpi=110)
    return 0


if __name__ == "__main__":
    sys.exit(main())
