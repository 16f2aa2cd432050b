#!/usr/bin/python3
"""Fits the cost model of `--accel auto` (accel/select/auto_model.h) on the benchmark's output.

usage: perf/model/fit_auto_model.py BENCH.json [BENCH.json ...] [--stale OLD.json ...] [--builds QUIET.json ...]
                                    [--scaled OLDER.json ...] [-o perf/model/auto_model.txt]
       perf/model/fit_auto_model.py perf/model/auto_model_data.csv      # refit from the kept table

Reads every arbor row (not Embree) of arbor-bench's bench.json that carries the job's shape
(rows[].shape: what auto knows before building, accel/select/job_shape.h) and fits, by ridge
regression on logarithms:
  trace: ln(ns per ray) per (structure, path) over TRACE_FEATURES, from the rows' trace CPU time /
         threads (median of the repeats: the time of an otherwise idle machine);
  build: ln(build ms) per structure over BUILD_FEATURES, from the fastest build of each scene.
Writes the model (the file CMake compiles into the library), the table it was fitted on
(auto_model_data.csv beside it, so the fit can be rerun and checked without the benchmark), and
prints how the model alone would pick on those rows: in-sample and leave-one-scene-out (every
scene predicted by a model fitted without it: how auto does on a scene it never saw).

Builds are timed by the wall clock (two threads share the work), so a run on a loaded machine
overrates them against the traces' CPU time (a model fitted on a loaded machine put bunny's bvh-sah
build at 108 ms, 29 ms on the quiet machine, and picked cheap builds at 1M rays). --builds takes the build
times from other runs instead (a quiet machine's; builds see no rays, so any ray seed will do): per
(scene, threads, structure) the median over those runs of each run's fastest build. --scaled adds
the rows of scenes the inputs lack from an older run (the large scenes of a full matrix), each time
scaled by the median ratio, inputs over older run, on the scenes both have, per (structure, path,
kind, threads): the code's speed-ups and the machine's load. They feed the trace fit only (builds
are fitted on the inputs' scenes; their slope in log2 triangles carries them to larger scenes).

The margin (when two predicted totals are too close for the model to tell apart) is the smallest
that, leave-one-scene-out, leaves a configuration more than 10% better than everything within the
margin outside it on at most MISS_RATE of the (scene, kind, threads, budget) rows: a perfect probe
of the configurations within the margin would then be within 10% of the best on the other rows.
"""
import argparse
import csv
import gzip
import json
import math
import os
import sys
from collections import defaultdict

import numpy as np

TRACE_FEATURES = ["one", "log2_triangles", "log_overlap", "log_spread", "log_size_tail", "log_thinness",
                  "coherent", "together", "any_hit", "log2_threads"]
BUILD_FEATURES = ["one", "log2_triangles", "log2_threads", "log_overlap", "log_thinness"]
RIDGE = 0.5           # on the standardised features (not on the intercept)
MISS_RATE = 0.10
SCALED = " (scaled)"  # the source of rows added by --scaled
MARGINS = [0.05 * i for i in range(1, 61)]
# The default structure, and the shares within which the model's decision prefers it to the predicted
# best: the model's ratio errors are ~19%, and a cheap build's trace penalty is what it misjudges
# most (lbvh or bvh-median picked at 1M rays where bvh-sah wins by 10-30%). The share is the one that
# does best leaving each scene out of the fit (ties: the smaller).
PREFERRED = "bvh-sah"
PREFER_SHARES = [0.0, 0.03, 0.05, 0.10]
SHAPE_KEYS = ["triangles", "overlap", "spread", "size_tail", "thinness", "coherent", "together", "any_hit"]


def feature(name, shape, threads):
    log = lambda v: math.log(max(v, 1e-6))
    return {
        "one": 1.0,
        "log2_triangles": math.log2(max(shape["triangles"], 1.0)),
        "log_overlap": log(shape["overlap"]),
        "log_spread": log(shape["spread"]),
        "log_size_tail": log(shape["size_tail"]),
        "log_thinness": log(shape["thinness"]),
        "coherent": shape["coherent"],
        "together": shape["together"],
        "any_hit": shape["any_hit"],
        "log2_threads": math.log2(max(threads, 1)),
    }[name]


def read_json(path):
    return json.load(gzip.open(path, "rt") if path.endswith(".gz") else open(path))


def run_name(path):
    """The run's folder name (bench.json's parent; a quiet run's runN folder keeps its parent's name too)."""
    d = os.path.dirname(os.path.abspath(path))
    name = os.path.basename(d)
    return (os.path.basename(os.path.dirname(d)) + "/" + name) if name.startswith("run") else name


def load(paths, stale=()):
    """Rows of the training table: one per (scene, kind, threads, structure, path). From the files in
    `stale` (bench.json written before the benchmark recorded the shape of the rays it timed), the
    primary and shadow rows timed on fewer rays than were validated are left out: their `coherent`
    and `together` are the validated finer image's, their times the coarser image's."""
    table = []
    for path in list(paths) + list(stale):
        if path.endswith(".csv"):
            with open(path) as f:
                for r in csv.DictReader(f):
                    row = {k: (v if k in ("scene", "kind", "structure", "path", "source") else float(v)) for k, v in r.items()}
                    row["threads"] = int(row["threads"])
                    table.append(row)
            continue
        data = read_json(path)
        for r in data["rows"]:
            if r["embree"] or not r.get("shape") or r["trace_cpu_ms"]["median"] is None or r["build_ms"]["min"] is None:
                continue
            if path in stale and r["kind"] in ("primary", "shadow") and r["rays"] < r.get("validated_rays", r["rays"]):
                continue
            row = {"source": run_name(path),
                   "scene": r["scene"], "kind": r["kind"], "structure": r["structure"], "path": r["path"],
                   "threads": int(r["threads"]), "rays": float(r["rays"]),
                   "ns_cpu": 1e6 * r["trace_cpu_ms"]["median"] / r["rays"],
                   "ns_wall": 1e6 * r["trace_ms"]["median"] / r["rays"],
                   "build_ms_min": r["build_ms"]["min"], "build_ms_median": r["build_ms"]["median"]}
            for k in SHAPE_KEYS:
                row[k] = float(r["shape"][k])
            table.append(row)
    if not table:
        sys.exit("fit_auto_model: no arbor rows with a shape in " + ", ".join(paths) + " (a bench.json from before shapes?)")
    return table


def quiet_builds(rows, paths):
    """Every row's build_ms_min replaced by the median over the runs `paths` of each run's fastest
    build of that (scene, threads, structure); rows those runs lack keep theirs. Returns the count replaced."""
    per_run = defaultdict(list)
    for path in paths:
        for r in read_json(path)["rows"]:
            if r["embree"] or r["build_ms"]["min"] is None:
                continue
            per_run[(r["scene"], float(r["triangles"]), int(r["threads"]), r["structure"])].append(r["build_ms"]["min"])
    # (each run lists a structure's build once per kind and path: the same samples; one per run)
    built = {k: sorted(set(v)) for k, v in per_run.items()}
    n = 0
    for r in rows:
        v = built.get((r["scene"], r["triangles"], r["threads"], r["structure"]))
        if v:
            r["build_ms_min"] = r["build_ms_median"] = v[len(v) // 2]
            n += 1
    return n


def median(v):
    v = sorted(v)
    return v[len(v) // 2] if len(v) % 2 else 0.5 * (v[len(v) // 2 - 1] + v[len(v) // 2])


def scaled_rows(rows, older):
    """The rows of `older` whose scenes `rows` lack, scaled to `rows` (see the module's doc). A scene is
    its name and triangle count (the quick matrix's grass is not the full matrix's)."""
    have = {(r["scene"], r["triangles"]) for r in rows}
    shared = [r for r in older if (r["scene"], r["triangles"]) in have]
    new = {(r["scene"], r["triangles"], r["kind"], r["structure"], r["path"], r["threads"]): r for r in rows}
    trace_ratio = defaultdict(list)
    for o in shared:
        n = new.get((o["scene"], o["triangles"], o["kind"], o["structure"], o["path"], o["threads"]))
        if not n:
            continue
        trace_ratio[(o["structure"], o["path"], o["kind"], o["threads"])].append(n["ns_cpu"] / o["ns_cpu"])
    out = []
    for o in older:
        if o["scene"] in {s for s, _ in have}:  # (another size of a scene the inputs have: left out)
            continue
        t = trace_ratio.get((o["structure"], o["path"], o["kind"], o["threads"]))
        if not t:
            continue
        r = dict(o)
        r["source"] = o["source"] + SCALED
        r["ns_cpu"] *= median(t)
        r["ns_wall"] *= median(t)
        out.append(r)
    return out


def design(rows, features):
    return np.array([[feature(f, r, r["threads"]) for f in features] for r in rows])


def ridge(X, y, lam=RIDGE):
    """Ridge regression on standardised columns (the intercept, column 0, unpenalised)."""
    mu = X[:, 1:].mean(axis=0)
    sd = X[:, 1:].std(axis=0)
    sd[sd < 1e-9] = 1.0
    Z = np.hstack([np.ones((len(X), 1)), (X[:, 1:] - mu) / sd])
    P = lam * np.eye(Z.shape[1])
    P[0, 0] = 0.0
    w = np.linalg.solve(Z.T @ Z + P, Z.T @ y)
    coef = np.empty_like(w)
    coef[1:] = w[1:] / sd
    coef[0] = w[0] - np.sum(w[1:] * mu / sd)
    return coef


def fit(rows):
    trace = {}
    for key in sorted({(r["structure"], r["path"]) for r in rows}):
        sel = [r for r in rows if (r["structure"], r["path"]) == key]
        trace[key] = ridge(design(sel, TRACE_FEATURES), np.log([r["ns_cpu"] for r in sel]))
    build = {}
    # (Rows scaled from an older run feed the traces only: their builds were timed on a loaded
    # machine, and one ratio per structure does not fix them: lbvh's 1M-triangle build at 2 threads
    # took 3.8x its 1-thread time there.)
    for s in sorted({r["structure"] for r in rows}):
        seen, sel = set(), []
        for r in rows:
            if r["source"].endswith(SCALED):
                continue
            if r["structure"] == s and (r["scene"], r["threads"], r["source"]) not in seen:
                seen.add((r["scene"], r["threads"], r["source"]))
                sel.append(r)
        build[s] = ridge(design(sel, BUILD_FEATURES), np.log([max(r["build_ms_min"], 1e-3) for r in sel]))
    clamps = {}
    for f in TRACE_FEATURES + BUILD_FEATURES:
        if f == "one":
            continue
        v = [feature(f, r, r["threads"]) for r in rows]
        clamps[f] = (min(v), max(v))
    return {"trace": trace, "build": build, "clamps": clamps}


def predict(model, r, structure, path):
    def val(f):
        v = feature(f, r, r["threads"])
        lo, hi = model["clamps"].get(f, (-1e300, 1e300))
        return min(max(v, lo), hi)
    ns = math.exp(sum(c * val(f) for c, f in zip(model["trace"][(structure, path)], TRACE_FEATURES)))
    build = math.exp(sum(c * val(f) for c, f in zip(model["build"][structure], BUILD_FEATURES)))
    return build, ns


def groups_of(rows):
    g = defaultdict(list)
    for r in rows:
        g[(r["source"], r["scene"], r["kind"], r["threads"])].append(r)
    return g


def model_pick(ptot, prefer):
    """The model's decision among predicted totals: the smallest, or PREFERRED's best configuration
    when that is predicted within `prefer` of it. Returns (smallest, pick)."""
    first = min(ptot, key=ptot.get)
    own = [k for k in ptot if k[0] == PREFERRED]
    if prefer > 0 and own:
        best_own = min(own, key=ptot.get)
        if ptot[best_own] <= ptot[first] * (1 + prefer):
            return first, best_own
    return first, first


def evaluate(rows, models_for, prefer=0.0, budgets=(1e6, 16e6, 256e6)):
    """How the model alone picks (no probe): within 10% of the best total (CPU time), and the
    errors of predicted ratios between configurations (for the margin). models_for(scene) gives
    the model to judge that scene with; `prefer` as in model_pick."""
    picks, ratio_errors = [], []
    misses = [0] * len(MARGINS)
    for key, g in groups_of(rows).items():
        model = models_for(key[1])
        g = [r for r in g if r["path"] != "scalar"]
        pred = {(r["structure"], r["path"]): predict(model, r, r["structure"], r["path"]) for r in g}
        for i, a in enumerate(g):
            for b in g[i + 1:]:
                pa, pb = pred[(a["structure"], a["path"])][1], pred[(b["structure"], b["path"])][1]
                ratio_errors.append(abs(math.log(pa / pb) - math.log(a["ns_cpu"] / b["ns_cpu"])))
        for budget in budgets:
            tot = {(r["structure"], r["path"]): r["build_ms_min"] + budget * r["ns_cpu"] * 1e-6 for r in g}
            ptot = {k: p[0] + budget * p[1] * 1e-6 for k, p in pred.items()}
            first, pick = model_pick(ptot, prefer)
            picks.append(tot[pick] / min(tot.values()) - 1.0)
            for i, m in enumerate(MARGINS):
                inside = min(tot[k] for k in tot if ptot[k] <= ptot[first] * (1 + m))
                misses[i] += min(tot.values()) * 1.10 < inside
    within = sum(p <= 0.10 for p in picks) / max(len(picks), 1)
    miss_rates = [m / max(len(picks), 1) for m in misses]
    return within, max(picks, default=0.0), sorted(ratio_errors), miss_rates


def write(model, margin, prefer, out, sources, rows, notes):
    lines = ["arbor-auto-model 1",
             "# The cost model of --accel auto (accel/select/auto_model.h). Written by",
             "# perf/model/fit_auto_model.py; do not edit: rerun the benchmark and the script.",
             f"source {', '.join(sources)} ({len(rows)} rows)"]
    lines += ["# " + n for n in notes]
    lines.append("trace_features " + " ".join(TRACE_FEATURES))
    lines.append("build_features " + " ".join(BUILD_FEATURES))
    for f, (lo, hi) in sorted(model["clamps"].items()):
        lines.append(f"clamp {f} {lo:.6g} {hi:.6g}")
    lines.append(f"margin {margin:.4f}")
    lines.append(f"prefer {PREFERRED} {prefer:.4f}")
    for s, coef in model["build"].items():
        lines.append(f"build {s} " + " ".join(f"{c:.6g}" for c in coef))
    for (s, p), coef in model["trace"].items():
        lines.append(f"trace {s} {p} " + " ".join(f"{c:.6g}" for c in coef))
    tmp = out + ".tmp"
    with open(tmp, "w") as f:
        f.write("\n".join(lines) + "\n")
    os.replace(tmp, out)


def write_table(rows, out):
    keys = ["source", "scene", "kind", "structure", "path", "threads", "rays", "ns_cpu", "ns_wall",
            "build_ms_min", "build_ms_median"] + SHAPE_KEYS
    tmp = out + ".tmp"
    with open(tmp, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=keys, extrasaction="ignore")
        w.writeheader()
        for r in rows:
            w.writerow({k: (f"{r[k]:.6g}" if isinstance(r[k], float) else r[k]) for k in keys})
    os.replace(tmp, out)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("inputs", nargs="+", help="bench.json files, or a table written by this script")
    here = os.path.dirname(os.path.abspath(__file__))
    ap.add_argument("-o", "--out", default=os.path.join(here, "auto_model.txt"))
    ap.add_argument("--table", default=None, help="where to write the training table (default: beside --out)")
    ap.add_argument("--stale", nargs="*", default=[], metavar="BENCH.json",
                    help="bench.json from before the rows carried the shape of fewer timed rays: its primary and "
                         "shadow rows timed on fewer rays than validated are left out")
    ap.add_argument("--builds", nargs="*", default=[], metavar="BENCH.json",
                    help="take the build times from these runs (a quiet machine's): see the module's doc")
    ap.add_argument("--scaled", nargs="*", default=[], metavar="BENCH.json",
                    help="add the rows of scenes the inputs lack from these older runs, scaled to the inputs "
                         "(their --stale rows left out): see the module's doc")
    a = ap.parse_args()
    rows = load(a.inputs, a.stale)
    if a.builds:
        n = quiet_builds(rows, a.builds)
        print(f"builds of {n} of {len(rows)} rows from {', '.join(a.builds)}")
    if a.scaled:
        extra = scaled_rows(rows, load([], a.scaled))
        print(f"{len(extra)} rows of {len({r['scene'] for r in extra})} scenes added, scaled, from {', '.join(a.scaled)}")
        rows += extra
    model = fit(rows)
    scenes = sorted({r["scene"] for r in rows})
    loso = {s: fit([r for r in rows if r["scene"] != s]) for s in scenes}
    by_share = {p: evaluate(rows, lambda s: loso[s], p)[0] for p in PREFER_SHARES}
    prefer = max(PREFER_SHARES, key=lambda p: (by_share[p], -p))
    in_within, in_worst, in_err, _ = evaluate(rows, lambda s: model, prefer)
    cv_within, cv_worst, cv_err, cv_miss = evaluate(rows, lambda s: loso[s], prefer)
    margin = next((m for m, r in zip(MARGINS, cv_miss) if r <= MISS_RATE), MARGINS[-1])
    miss_at = cv_miss[MARGINS.index(margin)]
    sources = sorted({r["source"] for r in rows})
    notes = [f"model alone, within 10% of the best build + trace total (CPU time; budgets 1M, 16M, 256M rays):",
             f"  in-sample {100 * in_within:.1f}% (worst {100 * in_worst:.0f}% over), "
             f"leave-one-scene-out {100 * cv_within:.1f}% (worst {100 * cv_worst:.0f}% over)",
             f"ratio errors between configurations: median {math.exp(cv_err[len(cv_err) // 2]) - 1:.3f} "
             f"(leave-one-scene-out), {math.exp(in_err[len(in_err) // 2]) - 1:.3f} (in-sample)",
             f"margin {margin:.2f}: leave-one-scene-out, a configuration more than 10% better than all within it lies "
             f"outside it on {100 * miss_at:.1f}% of the rows (target <= {100 * MISS_RATE:.0f}%)",
             f"prefer {PREFERRED} within {prefer:.2f} of the best prediction: leave-one-scene-out within 10% " +
             ", ".join(f"{100 * by_share[p]:.1f}% at {p:.2f}" for p in PREFER_SHARES)]
    if a.builds:
        notes.insert(0, "builds from " + ", ".join(run_name(b) for b in a.builds) +
                     " (per scene and threads the median over those runs of each run's fastest build)")
    write(model, margin, prefer, a.out, sources, rows, notes)
    write_table(rows, a.table or os.path.join(os.path.dirname(os.path.abspath(a.out)), "auto_model_data.csv"))
    print(f"{a.out}: {len(rows)} rows from {', '.join(sources)}; margin {margin:.3f}, prefer {PREFERRED} {prefer:.2f}")
    for n in notes:
        print(n)


if __name__ == "__main__":
    main()
