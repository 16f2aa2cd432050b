#!/usr/bin/env python3
"""Meshes that move: Scene.update_vertices refitting against rebuilding (docs/refit.md).

Two tables, both through the Python module (each figure the wall clock of whole calls, as a user
waits for them):
  1. refit vs rebuild of one update of a ~1M-triangle mesh (a bumpy sphere) per structure: the
     median of --rounds updates in each mode, interleaved (refit, rebuild, refit, ...), each to a
     new pose of a travelling sine wave;
  2. an animation: a model deformed over --steps steps (the same wave), each step one update and
     one batch of incoherent rays (Scene.intersect); total wall clock of the whole animation with
     mode="refit", mode="rebuild" and mode="auto", per row (model, rays per step, wave amplitude),
     the modes' order rotated round by round and the median of --anim-rounds kept per mode. Every
     step's hits of the three modes are compared (t, geom, prim, u, v, bit for bit).
Writes a Markdown report (--out) and the same figures as JSON beside it.

  PYTHONPATH=build/release/python python3 scripts/bench_refit.py --out build/results/refit.md
"""
import argparse
import json
import os
import pathlib
import re
import statistics
import sys
import time

import numpy as np

import arbor

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent.parent / "python" / "tests"))
from deform import pose, read_obj  # noqa: E402  (the update tests' deforming model)


def bumpy_sphere(triangles):
    """A UV sphere of about `triangles` triangles with a little radial noise (deterministic)."""
    nu = int(np.sqrt(triangles))
    nv = max(4, triangles // (2 * nu))
    u = np.linspace(0, 2 * np.pi, nu, endpoint=False)
    w = np.linspace(0.01, np.pi - 0.01, nv)
    uu, ww = np.meshgrid(u, w)
    r = 1.0 + 0.02 * np.random.default_rng(1).standard_normal(uu.shape)
    v = np.stack([r * np.sin(ww) * np.cos(uu), r * np.sin(ww) * np.sin(uu), r * np.cos(ww)], axis=-1).reshape(-1, 3)
    i = np.arange(nv - 1)[:, None] * nu
    j = np.arange(nu)[None, :]
    a, b = i + j, i + (j + 1) % nu
    c, d = a + nu, b + nu
    f = np.concatenate([np.stack([a, b, d], -1).reshape(-1, 3), np.stack([a, d, c], -1).reshape(-1, 3)])
    return v.astype(np.float32), f.astype(np.uint32)


def rays_into(v, n, seed):
    """Incoherent rays: from a sphere around the box towards random points inside it."""
    rng = np.random.default_rng(seed)
    lo, hi = v.min(axis=0), v.max(axis=0)
    c, r = (lo + hi) / 2, float(np.linalg.norm(hi - lo))
    d = rng.normal(size=(n, 3))
    o = c + r * d / np.linalg.norm(d, axis=1, keepdims=True)
    t = lo + rng.random((n, 3)) * (hi - lo)
    return o.astype(np.float32), (t - o).astype(np.float32)


def timed(f):
    t0 = time.perf_counter()
    f()
    return (time.perf_counter() - t0) * 1e3


def own_ms(reason, what):
    """What the structure's own `what` ("refit", "rebuild") took, from the reason's end."""
    m = re.search(r"the " + what + r"(?: took)? ([0-9.]+) ms", reason)
    return float(m.group(1)) if m else float("nan")


def update_table(args):
    v, f = bumpy_sphere(args.triangles)
    rows = []
    for accel in args.accels:
        s = arbor.Scene(v, f)
        s.build(accel, threads=args.threads)
        times = {"refit": [], "rebuild": []}
        own = {"refit": [], "rebuild": []}
        reasons = {}
        for r in range(args.rounds):
            for mode in ("refit", "rebuild") if r % 2 == 0 else ("rebuild", "refit"):
                p = pose(v, 2 * r + (mode == "rebuild"), 0.02)
                times[mode].append(timed(lambda: s.update_vertices(0, p, mode=mode)))
                reasons[mode] = s.update_reason
                own[mode].append(own_ms(s.update_reason, mode))
        refit, rebuild = statistics.median(times["refit"]), statistics.median(times["rebuild"])
        own_refit, own_rebuild = statistics.median(own["refit"]), statistics.median(own["rebuild"])
        rows.append({"accel": accel, "triangles": int(len(f)), "refit_ms": refit, "rebuild_ms": rebuild,
                     "refit_ms_all": times["refit"], "rebuild_ms_all": times["rebuild"], "speedup": rebuild / refit,
                     "own_refit_ms": own_refit, "own_rebuild_ms": own_rebuild, "own_speedup": own_rebuild / own_refit,
                     "refit_reason": reasons["refit"], "rebuild_reason": reasons["rebuild"]})
        print(f"update {accel}: refit {refit:.1f} ms, rebuild {rebuild:.1f} ms, {rebuild / refit:.1f}x; "
              f"structure alone {own_refit:.1f} / {own_rebuild:.1f} ms, {own_rebuild / own_refit:.1f}x", flush=True)
    return rows


MODES = ("refit", "rebuild", "auto")


def animation_round(rest, faces, amplitude, steps, o, d, accel, threads):
    """One round: three scenes, one per mode, stepped in lockstep (each step, every mode's update +
    intersect timed, the modes' order rotated step by step, so that the shared machine's load
    falls on all three alike). Returns the total ms per mode, auto's actions, whether the hits of
    the three agreed at every step."""
    scenes = {}
    for mode in MODES:
        s = arbor.Scene(pose(rest, 0, amplitude), faces)
        s.build(accel, threads=threads)
        s.intersect(o, d, threads=threads)  # the rays of step 0: what auto measures before step 1
        scenes[mode] = s
    totals = dict.fromkeys(MODES, 0.0)
    actions, agree = [], True
    for step in range(1, steps + 1):
        v = pose(rest, step, amplitude)
        hits = {}
        for k in range(3):
            mode = MODES[(step + k) % 3]
            s = scenes[mode]
            t0 = time.perf_counter()
            s.update_vertices(0, v, mode=mode)
            hits[mode] = s.intersect(o, d, threads=threads)
            totals[mode] += (time.perf_counter() - t0) * 1e3
        actions.append(scenes["auto"].update_action)
        agree = agree and hits["refit"].tobytes() == hits["rebuild"].tobytes() == hits["auto"].tobytes()
    return totals, actions, agree


def animation_table(args):
    rows = []
    models = [(pathlib.Path(args.model).name, *read_obj(args.model))]
    if args.anim_triangles:
        models.append((f"bumpy sphere {args.anim_triangles // 1000}k", *bumpy_sphere(args.anim_triangles)))
    for name, rest, faces in models:
        for amplitude in args.amplitudes:
            for nrays in args.rays:
                o, d = rays_into(pose(rest, 0, amplitude), nrays, 7)
                totals = {m: [] for m in MODES}
                agree, rebuilds = True, []
                for _ in range(args.anim_rounds):
                    t, acts, ok = animation_round(rest, faces, amplitude, args.steps, o, d, args.anim_accel, args.threads)
                    for m in MODES:
                        totals[m].append(t[m])
                    agree = agree and ok
                    rebuilds.append(acts.count("rebuild"))
                med = {m: statistics.median(t) for m, t in totals.items()}
                best = min(med["refit"], med["rebuild"])
                row = {"model": name, "triangles": int(len(faces)), "amplitude": amplitude, "rays": nrays,
                       "steps": args.steps, "refit_ms": med["refit"], "rebuild_ms": med["rebuild"], "auto_ms": med["auto"],
                       "all_ms": totals, "auto_vs_best": med["auto"] / best,
                       "auto_rebuilds": statistics.median(rebuilds), "identical_hits": agree}
                rows.append(row)
                print(f"{name} a={amplitude} rays={nrays}: refit {med['refit']:.0f} rebuild {med['rebuild']:.0f} "
                      f"auto {med['auto']:.0f} ms ({row['auto_vs_best']:.3f} of the better; {rebuilds} rebuilds), "
                      f"identical {agree}", flush=True)
    return rows


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    root = pathlib.Path(__file__).resolve().parents[1]
    scenes = os.environ.get("ARBOR_SHARED_SCENES", str(root / ".." / "shared" / "scenes"))
    ap.add_argument("--triangles", type=int, default=1_000_000, help="the update table's mesh (default 1M)")
    ap.add_argument("--accels", nargs="+", default=["bvh-sah", "lbvh", "bvh-median", "kdtree"])
    ap.add_argument("--rounds", type=int, default=7, help="updates per mode in the update table")
    ap.add_argument("--model", default=str(pathlib.Path(scenes) / "models" / "stanford-bunny.obj"))
    ap.add_argument("--anim-triangles", type=int, default=0, help="also animate a bumpy sphere of this size")
    ap.add_argument("--anim-accel", default="bvh-sah")
    ap.add_argument("--steps", type=int, default=100)
    ap.add_argument("--rays", type=int, nargs="+", default=[1000, 30000, 300000])
    ap.add_argument("--amplitudes", type=float, nargs="+", default=[0.02, 0.2])
    ap.add_argument("--anim-rounds", type=int, default=3)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--skip-update", action="store_true")
    ap.add_argument("--skip-animation", action="store_true")
    ap.add_argument("--out", default="build/results/refit.md")
    args = ap.parse_args()

    started = time.strftime("%H:%M", time.gmtime())
    upd = [] if args.skip_update else update_table(args)
    anim = [] if args.skip_animation else animation_table(args)
    ended = time.strftime("%H:%M", time.gmtime())
    out = pathlib.Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    load = os.getloadavg()[0]
    lines = ["# Meshes that move: refit against rebuild", "",
             f"arbor {arbor.__version__}, kernels {arbor.kernel_set()}, {args.threads} threads, "
             f"{started}-{ended} UTC, load average {load:.1f} at the end.", "", "```sh",
             "PYTHONPATH=build/release/python python3 scripts/bench_refit.py " + " ".join(sys.argv[1:]), "```", ""]
    if upd:
        lines += [f"## One update of a {upd[0]['triangles']:,}-triangle mesh (median of {args.rounds}, interleaved)", "",
                  "Whole call: `update_vertices` as Python waits for it (argument checks, the positions copied, the",
                  "structure's work). Structure alone: the refit or the build itself (the reason's `[...]` figure).", "",
                  "| structure | whole call: refit ms | rebuild ms | rebuild / refit | structure alone: refit ms | rebuild ms | rebuild / refit |",
                  "|---|---:|---:|---:|---:|---:|---:|"]
        for r in upd:
            lines.append(f"| {r['accel']} | {r['refit_ms']:.1f} | {r['rebuild_ms']:.1f} | **{r['speedup']:.1f}x** | "
                         f"{r['own_refit_ms']:.1f} | {r['own_rebuild_ms']:.1f} | **{r['own_speedup']:.1f}x** |")
        lines.append("")
    if anim:
        lines += [f"## An animation: {args.steps} steps of update + intersect ({args.anim_accel}; total ms, median of "
                  f"{args.anim_rounds} rounds)", "",
                  "| model | triangles | wave amplitude | rays per step | refit ms | rebuild ms | auto ms | auto / better | auto's rebuilds | identical hits |",
                  "|---|---:|---:|---:|---:|---:|---:|---:|---:|---|"]
        for r in anim:
            lines.append(f"| {r['model']} | {r['triangles']:,} | {r['amplitude']} | {r['rays']:,} | {r['refit_ms']:.0f} | "
                         f"{r['rebuild_ms']:.0f} | {r['auto_ms']:.0f} | **{r['auto_vs_best']:.3f}** | "
                         f"{r['auto_rebuilds']:g}/{r['steps']} | {'yes' if r['identical_hits'] else 'NO'} |")
        lines.append("")
    out.write_text("\n".join(lines))
    out.with_suffix(".json").write_text(json.dumps({"update": upd, "animation": anim}, indent=1))
    print("\n".join(lines))


if __name__ == "__main__":
    main()
