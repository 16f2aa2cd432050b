#!/usr/bin/env python3
"""arbor against the faster Embree, per cell, from held-out reports of scripts/bench_heldout.sh run
once against each Embree (e.g. 3.13 and, with EMBREE4=PREFIX, 4.x) on the same ray files.

In each report, a cell's ratio is arbor's default (the faster structure on its `best` path) over
that Embree's fastest call, both measured in the same run. Against the faster of the Embrees, a
cell's ratio is the smaller of the reports' ratios (each stays a within-run ratio; no rate is
compared across runs). Prints per kind: cells, min, median, the worst cell, and how many cells each
Embree was the harder peer in.

    scripts/heldout_faster_peer.py REPORT_E3.md REPORT_E4.md [...]
"""
import re
import statistics
import sys
from collections import defaultdict

CELL = re.compile(r"^\| ([^|]+?) \| ([a-z-]+) \| [^|]+ \|(.*)\|\s*$")
RATIO = re.compile(r"\*\*([0-9.]+)x\*\* \(([^)]*)\)")


def default_ratio(text):
    """The ratio of a structure's `best` path in one table entry: `**1.20x** (best)` or
    `**1.59x** (packet; best 1.54x)`."""
    m = RATIO.search(text)
    if not m:
        return None
    fastest, note = float(m.group(1)), m.group(2)
    b = re.search(r"best ([0-9.]+)x", note)
    return float(b.group(1)) if b else fastest


def read(path):
    """{(scene, kind): arbor default / this Embree}, and the Embree version of the title."""
    cells, peer = {}, "?"
    for line in open(path):
        t = re.match(r"(?:# .*|- peer: )Embree ([0-9][0-9.]*)", line)
        if t:
            peer = t.group(1)
        if line.startswith("## ") and cells:
            break  # the per-cell table is the first one
        m = CELL.match(line)
        if not m or m.group(1) == "scene":
            continue
        ratios = [default_ratio(e) for e in m.group(3).split("|")]
        ratios = [r for r in ratios if r is not None]
        if ratios:
            cells[(m.group(1), m.group(2))] = max(ratios)
    return peer, cells


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    reports = [read(p) for p in sys.argv[1:]]
    common = set.intersection(*(set(c) for _, c in reports))
    if not common:
        sys.exit("heldout_faster_peer.py: the reports share no (scene, kind) cell")
    by_kind = defaultdict(list)
    for cell in sorted(common):
        ratios = [c[cell] for _, c in reports]
        k = min(range(len(ratios)), key=ratios.__getitem__)
        by_kind[cell[1]].append((ratios[k], cell[0], reports[k][0]))
    peers = " and ".join(p for p, _ in reports)
    print(f"arbor default / the faster of Embree {peers}, per cell (the smaller within-run ratio)\n")
    print("| kind | cells | min | median | worst cell | cells where each Embree was the harder peer |")
    print("|---|---:|---:|---:|---|---|")
    for kind, rows in by_kind.items():
        rows.sort()
        harder = ", ".join(f"{p}: {sum(1 for r in rows if r[2] == p)}" for p, _ in reports)
        med = statistics.median(r[0] for r in rows)
        print(f"| {kind} | {len(rows)} | {rows[0][0]:.2f} | **{med:.2f}** | {rows[0][1]} ({rows[0][2]}) | {harder} |")


if __name__ == "__main__":
    main()
