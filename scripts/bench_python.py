#!/usr/bin/env python3
"""Scene.intersect from Python against `arbor trace` on the same rays and structure.

For each ray kind, `arbor rays` writes N rays of the model; then, interleaved round by round, two
pairs are timed:
  * the query, both sides in a fresh process that loads the model, builds the structure, reads
    the rays and then traces them K times, each trace timed: `arbor trace --json --repeat K` (its
    median trace_ms: the time inside the structure; its hit vector is allocated and zeroed before
    the timing and reused by every repeat) against python3 making K calls of Scene.intersect
    (each the whole call a Python user waits for: argument checks, the path decision, the trace
    on every thread, a new result array written with geometry ids), median of K; the Python
    process also reports the CPU time of a call (both threads) and, alternated with those calls,
    K calls with out= (the last result array reused) when the module has it. Both start timing right after their own build,
    the same state: a process timed after a pause (a long-lived one that slept while
    `arbor trace` ran) is ~1.5x slower on its first calls on a loaded machine;
  * with --baseline DIR, the same Python run through another build of the module (DIR holds its
    `arbor` package; DIR/lib, when present, its libarbor.so): the A/B of two builds in one run,
    the order of the processes rotated round by round;
  * the whole job, a fresh process each: `arbor trace` (load, build, read the rays, trace once)
    against `python3` running the same with arbor (import, Scene.load, build, read_rays, intersect),
    wall clock.
The hits of all are compared record by record (t, prim, u, v, bit for bit). Writes a Markdown report.

  PYTHONPATH=build/release/python python3 scripts/bench_python.py --out build/results/python.md
"""
import argparse
import json
import os
import pathlib
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

import arbor


# One timed run of the module, in a fresh process as `arbor trace` is: load, build, read the rays,
# then K calls of Scene.intersect (each followed by one with out= when the module has it), each timed.
TIMED = r"""
import json, sys, time, numpy as np, arbor
model, accel, threads, rays, k, hits = sys.argv[1:7]
scene = arbor.Scene.load(model)
scene.build(accel, threads=int(threads))
o, d, tn, tf = arbor.read_rays(rays)
res = {"version": arbor.__version__, "kernels": arbor.kernel_set(), "wall": [], "cpu": [], "out_wall": []}
h = None
try:
    scene.intersect(o[:1], d[:1], out=np.empty(1, arbor.hit_dtype))
    has_out = True
except TypeError:  # a build of the module without out=
    has_out = False
for _ in range(int(k)):  # a new result array, then (alternated) the last one reused via out=
    c0, t0 = time.process_time(), time.perf_counter()
    h = scene.intersect(o, d, tn, tf)
    res["wall"].append(time.perf_counter() - t0)
    res["cpu"].append(time.process_time() - c0)
    if has_out:
        t0 = time.perf_counter()
        scene.intersect(o, d, tn, tf, out=h)
        res["out_wall"].append(time.perf_counter() - t0)
if hits:
    np.save(hits, h)
print(json.dumps(res))
"""


def timed_run(a, pythonpath, rays, hits=""):
    """TIMED in a fresh python3 with the module at `pythonpath` (None: this environment's)."""
    env = dict(os.environ)
    if pythonpath:
        env["PYTHONPATH"] = pythonpath
        lib = pathlib.Path(pythonpath, "lib")
        if lib.is_dir():
            env["LD_LIBRARY_PATH"] = str(lib) + os.pathsep + env.get("LD_LIBRARY_PATH", "")
    out = subprocess.run([sys.executable, "-c", TIMED, a.model, a.accel, str(a.threads), str(rays), str(a.repeat), hits],
                         env=env, check=True, capture_output=True, text=True).stdout
    return json.loads(out)


HIT = [("t", "<f4"), ("prim", "<u4"), ("u", "<f4"), ("v", "<f4")]


def same_hits(rec, h):
    return int(np.count_nonzero((rec["t"].view("<u4") == h["t"].view("<u4")) & (rec["prim"] == h["prim"])
                                & (rec["u"].view("<u4") == h["u"].view("<u4")) & (rec["v"].view("<u4") == h["v"].view("<u4"))))


def main():
    root = pathlib.Path(__file__).resolve().parents[1]
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--arbor", default=str(root / "build/release/apps/arbor/arbor"))
    ap.add_argument("--model", default=str(root / "../shared/scenes/models/stanford-bunny.obj"))
    ap.add_argument("--kinds", default="primary,shadow,diffuse,random")
    ap.add_argument("--rays", type=int, default=1_000_000)
    ap.add_argument("--accel", default="bvh-sah")
    ap.add_argument("--threads", type=int, default=0, help="0 = all cores")
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--baseline", help="PYTHONPATH of another build of the module to A/B against (DIR/lib: its libarbor.so)")
    ap.add_argument("--no-whole-job", action="store_true", help="skip the fresh-process timings")
    ap.add_argument("--out", help="Markdown report")
    ap.add_argument("--queries", type=int, default=0,
                    help="also time every query on every structure with this many rays / points (0: skip)")
    a = ap.parse_args()

    workers = {"new": None}
    if a.baseline:
        workers["old"] = a.baseline
    info = {}
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for kind in a.kinds.split(","):
            rays = pathlib.Path(tmp, f"{kind}.rays")
            subprocess.run([a.arbor, "rays", "--scene", a.model, "--kind", kind, "--count", str(a.rays), "-o", str(rays)],
                           check=True, stdout=subprocess.DEVNULL)
            hits_file = pathlib.Path(tmp, f"{kind}.hits")
            cli, cli_wall, py_wall = [], [], []
            py = {w: [] for w in workers}
            cpu = {w: [] for w in workers}
            out_call = {w: [] for w in workers}
            job = (f"import arbor\ns = arbor.Scene.load({str(a.model)!r})\ns.build({a.accel!r}, threads={a.threads})\n"
                   f"o, d, tn, tf = arbor.read_rays({str(rays)!r})\nh = s.intersect(o, d, tn, tf)\n")
            for r in range(a.rounds):
                cmd = [a.arbor, "trace", "--scene", a.model, "--rays", str(rays), "--accel", a.accel, "--json"]
                if a.threads:
                    cmd += ["--threads", str(a.threads)]
                j = json.loads(subprocess.run(cmd + ["--repeat", str(a.repeat)] + (["--hits", str(hits_file)] if r == 0 else []),
                                              check=True, capture_output=True, text=True).stdout)
                cli.append(j["mrays_per_s"])
                names = list(workers)
                for w in names[r % len(names):] + names[:r % len(names)]:
                    res = timed_run(a, workers[w], rays, f"{tmp}/{w}.npy" if r == 0 else "")
                    info = info or res
                    n = a.rays
                    py[w].append(n / statistics.median(res["wall"]) / 1e6)
                    cpu[w].append(statistics.median(res["cpu"]) * 1e3)
                    if res["out_wall"]:
                        out_call[w].append(n / statistics.median(res["out_wall"]) / 1e6)
                if not a.no_whole_job:
                    # The whole job in a fresh process each (A/B in the same round).
                    t0 = time.perf_counter()
                    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
                    cli_wall.append(time.perf_counter() - t0)
                    t0 = time.perf_counter()
                    subprocess.run([sys.executable, "-c", job], check=True)
                    py_wall.append(time.perf_counter() - t0)
            # The CLI's hits: 16-byte records t, prim, u, v after a 16-byte header.
            rec = np.frombuffer(hits_file.read_bytes()[16:], dtype=HIT)
            same = {}
            for w in workers:
                same[w] = same_hits(rec, np.load(f"{tmp}/{w}.npy"))
            ratios = {w: [p / c for p, c in zip(py[w], cli)] for w in workers}
            wall = [c / p for p, c in zip(py_wall, cli_wall)]
            row = {"kind": kind, "cli": statistics.median(cli), "n": len(rec), "path": j["path"], "threads": j["threads"],
                   "py": {w: statistics.median(py[w]) for w in workers}, "same": same,
                   "ratio": {w: (statistics.median(ratios[w]), min(ratios[w]), max(ratios[w])) for w in workers},
                   "cpu": {w: statistics.median(cpu[w]) for w in workers},
                   "out": {w: (statistics.median(out_call[w]), statistics.median([p / c for p, c in zip(out_call[w], cli)]))
                           for w in workers if out_call[w]}}
            if a.baseline:
                ab = [n / o for n, o in zip(py["new"], py["old"])]
                row["ab"] = (statistics.median(ab), min(ab), max(ab))
            if wall:
                row["whole"] = (statistics.median(cli_wall), statistics.median(py_wall), statistics.median(wall), min(wall),
                                max(wall))
            rows.append(row)
            print(f"{kind}: arbor trace {row['cli']:.2f} Mrays/s; " + "; ".join(
                f"{w} Scene.intersect {row['py'][w]:.2f} Mrays/s, ratio {row['ratio'][w][0]:.3f} "
                f"({row['ratio'][w][1]:.3f}-{row['ratio'][w][2]:.3f}), identical hits {same[w]}/{len(rec)}" for w in workers)
                  + (f"; new/old {row['ab'][0]:.3f}" if a.baseline else ""), flush=True)
    table = report_table(a, rows, list(workers))
    if a.queries:
        table += "\n\n" + queries_table(a)
    print(table)
    if a.out:
        pathlib.Path(a.out).parent.mkdir(parents=True, exist_ok=True)
        cmd = " ".join([os.path.relpath(sys.argv[0], root)] + sys.argv[1:])
        pathlib.Path(a.out).write_text(
            f"# Scene.intersect (Python) against `arbor trace`\n\nModel `{pathlib.Path(a.model).name}`, "
            f"{a.rays} rays per kind, structure `{a.accel}`, {a.rounds} interleaved rounds, each a median of "
            f"{a.repeat}; arbor {info['version']}, kernels {info['kernels']}.\n\n```sh\nPYTHONPATH=build/release/python "
            f"python3 {cmd}\n```\n\n{table}\n")


def report_table(a, rows, names):
    label = {"new": "Scene.intersect", "old": "baseline Scene.intersect"}
    head = ["rays", "arbor trace Mrays/s (trace_ms)"]
    for w in names:
        head += [f"{label[w]} Mrays/s (whole call)", f"ratio (median, min-max of {a.rounds} rounds)", "CPU ms per call"]
    if a.baseline:
        head += ["new / baseline (median, min-max)"]
    if any(r["out"] for r in rows):
        head += ["out= call Mrays/s, ratio"]
    head += ["identical hits (t, prim, u, v)", "path", "threads"]
    if any("whole" in r for r in rows):
        head += ["whole job: arbor trace s", "whole job: python3 s", "ratio"]
    lines = ["| " + " | ".join(head) + " |", "|" + "|".join("---" if i == 0 else "---:" for i in range(len(head))) + "|"]
    for r in rows:
        cells = [r["kind"], f"{r['cli']:.2f}"]
        for w in names:
            m, lo, hi = r["ratio"][w]
            cells += [f"{r['py'][w]:.2f}", f"**{m:.3f}** ({lo:.3f}-{hi:.3f})", f"{r['cpu'][w]:.1f}"]
        if a.baseline:
            cells += ["{:.3f} ({:.3f}-{:.3f})".format(*r["ab"])]
        if any(x["out"] for x in rows):
            cells += [f"{r['out']['new'][0]:.2f}, {r['out']['new'][1]:.3f}" if "new" in r["out"] else "-"]
        cells += [" / ".join(f"{r['same'][w]}/{r['n']}" for w in names), r["path"], str(r["threads"])]
        if "whole" in r:
            cl, pw, m, lo, hi = r["whole"]
            cells += [f"{cl:.3f}", f"{pw:.3f}", f"{m:.3f} ({lo:.3f}-{hi:.3f})"]
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


def timed(fn, repeat):
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times), out


def queries_table(a):
    """Every query on every structure: million queries per second (median of --repeat, the whole
    call), and the share of a 1,000-query subset whose answer equals brute force's bit for bit."""
    scene = arbor.Scene.load(a.model)
    lo, hi = scene.bounds
    rng = np.random.default_rng(1)
    n = a.queries
    c, r = (lo + hi) / 2, np.linalg.norm(hi - lo)
    d = rng.normal(size=(n, 3))
    o = (c + r * d / np.linalg.norm(d, axis=1, keepdims=True)).astype(np.float32)
    dirs = (lo + rng.random((n, 3)) * (hi - lo) - o).astype(np.float32)
    pts = (lo - 0.1 * (hi - lo) + rng.random((n, 3)) * 1.2 * (hi - lo)).astype(np.float32)
    k = 1000
    scene.build("brute", threads=a.threads)
    ref = {"intersect_all": scene.intersect_all(o[:k], dirs[:k])[0].tobytes(),
           "closest_point": scene.closest_point(pts[:k]), "inside": scene.inside(pts[:k])}
    rows = [f"Every query on every structure, {n} random rays into the box / points in the box grown by 10%, "
            f"{a.threads or 'all'} threads; M/s of the whole call (median of {a.repeat}); 'same' = answers equal to "
            "brute force's, bit for bit, on the first 1,000.", "",
            "| structure | intersect M rays/s | intersect_all (16) M rays/s, same | closest_point M points/s, same | "
            "inside M points/s, same |", "|---|---:|---:|---:|---:|"]
    for name in ["bvh-sah", "bvh-median", "lbvh", "kdtree"]:
        scene.build(name, threads=a.threads)
        ti, _ = timed(lambda: scene.intersect(o, dirs), a.repeat)
        ta, (hits, _) = timed(lambda: scene.intersect_all(o, dirs), a.repeat)
        tc, cp = timed(lambda: scene.closest_point(pts), a.repeat)
        tn, ins = timed(lambda: scene.inside(pts), a.repeat)
        same_a = sum(hits[i].tobytes() == ref["intersect_all"][i * 320:(i + 1) * 320] for i in range(k))
        same_c = sum(cp[i:i + 1].tobytes() == ref["closest_point"][i:i + 1].tobytes() for i in range(k))
        same_n = int(np.count_nonzero(ins[:k] == ref["inside"]))
        rows.append(f"| {name} | {n / ti / 1e6:.2f} | {n / ta / 1e6:.2f}, {same_a}/{k} | {n / tc / 1e6:.3f}, {same_c}/{k} | "
                    f"{n / tn / 1e6:.2f}, {same_n}/{k} |")
        print(rows[-1], flush=True)
    return "\n".join(rows)


if __name__ == "__main__":
    main()
