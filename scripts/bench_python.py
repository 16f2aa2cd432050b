#!/usr/bin/env python3
"""Scene.intersect from Python against `arbor trace` on the same rays and structure.

For each ray kind, `arbor rays` writes N rays of the model; then, interleaved round by round, two
pairs are timed:
  * the query: one `arbor trace --json --repeat K` process (its median trace_ms: the time inside
    the structure) against K calls of Scene.intersect in this process on the same rays (each the
    whole call a Python user waits for: argument checks, the trace on every thread, the result
    array), median of K;
  * the whole job, a fresh process each: `arbor trace` (load, build, read the rays, trace once)
    against `python3` running the same with arbor (import, Scene.load, build, read_rays, intersect),
    wall clock.
The hits of both are compared record by record (t and prim, bit for bit). Writes a Markdown report.

  PYTHONPATH=build/release/python python3 scripts/bench_python.py --out perf/results/python-DATE.md
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
    ap.add_argument("--out", help="Markdown report")
    ap.add_argument("--queries", type=int, default=0,
                    help="also time every query on every structure with this many rays / points (0: skip)")
    a = ap.parse_args()

    scene = arbor.Scene.load(a.model)
    scene.build(a.accel, threads=a.threads)
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for kind in a.kinds.split(","):
            rays = pathlib.Path(tmp, f"{kind}.rays")
            subprocess.run([a.arbor, "rays", "--scene", a.model, "--kind", kind, "--count", str(a.rays), "-o", str(rays)],
                           check=True, stdout=subprocess.DEVNULL)
            o, d, tn, tf = arbor.read_rays(rays)
            hits_file = pathlib.Path(tmp, f"{kind}.hits")
            cli, py, cli_wall, py_wall = [], [], [], []
            job = (f"import arbor\ns = arbor.Scene.load({str(a.model)!r})\ns.build({a.accel!r}, threads={a.threads})\n"
                   f"o, d, tn, tf = arbor.read_rays({str(rays)!r})\nh = s.intersect(o, d, tn, tf)\n")
            for r in range(a.rounds):
                cmd = [a.arbor, "trace", "--scene", a.model, "--rays", str(rays), "--accel", a.accel, "--json"]
                if a.threads:
                    cmd += ["--threads", str(a.threads)]
                j = json.loads(subprocess.run(cmd + ["--repeat", str(a.repeat)] + (["--hits", str(hits_file)] if r == 0 else []),
                                              check=True, capture_output=True, text=True).stdout)
                cli.append(j["mrays_per_s"])
                times = []
                for _ in range(a.repeat):
                    t0 = time.perf_counter()
                    h = scene.intersect(o, d, tn, tf)
                    times.append(time.perf_counter() - t0)
                py.append(len(o) / statistics.median(times) / 1e6)
                # The whole job in a fresh process each (A/B in the same round).
                t0 = time.perf_counter()
                subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
                cli_wall.append(time.perf_counter() - t0)
                t0 = time.perf_counter()
                subprocess.run([sys.executable, "-c", job], check=True)
                py_wall.append(time.perf_counter() - t0)
            # The CLI's hits: 16-byte records t, prim, u, v after a 16-byte header.
            rec = np.frombuffer(hits_file.read_bytes()[16:], dtype=[("t", "<f4"), ("prim", "<u4"), ("u", "<f4"), ("v", "<f4")])
            same = int(np.count_nonzero((rec["t"].view("<u4") == h["t"].view("<u4")) & (rec["prim"] == h["prim"])
                                        & (rec["u"].view("<u4") == h["u"].view("<u4")) & (rec["v"].view("<u4") == h["v"].view("<u4"))))
            ratios = [p / c for p, c in zip(py, cli)]
            wall = [c / p for p, c in zip(py_wall, cli_wall)]
            rows.append((kind, statistics.median(cli), statistics.median(py), statistics.median(ratios), min(ratios),
                         max(ratios), same, len(o), j["path"], j["threads"], statistics.median(cli_wall),
                         statistics.median(py_wall), statistics.median(wall), min(wall), max(wall)))
            print(f"{kind}: arbor trace {rows[-1][1]:.2f} Mrays/s, Scene.intersect {rows[-1][2]:.2f} Mrays/s, "
                  f"ratio {rows[-1][3]:.3f} ({rows[-1][4]:.3f}-{rows[-1][5]:.3f}); whole job {rows[-1][10]:.3f} s vs "
                  f"{rows[-1][11]:.3f} s, ratio {rows[-1][12]:.3f}; identical hits {same}/{len(o)}", flush=True)
    lines = [f"| rays | arbor trace Mrays/s (trace_ms) | Scene.intersect Mrays/s (whole call) | ratio (median, min-max of "
             f"{a.rounds} rounds) | whole job: arbor trace s | whole job: python3 s | ratio | identical hits (t, prim, u, v) "
             "| path | threads |", "|---|---:|---:|---|---:|---:|---|---:|---|---:|"]
    for k, c, p, r, lo, hi, same, n, path, thr, cw, pw, wr, wlo, whi in rows:
        lines.append(f"| {k} | {c:.2f} | {p:.2f} | **{r:.3f}** ({lo:.3f}-{hi:.3f}) | {cw:.3f} | {pw:.3f} | {wr:.3f} "
                     f"({wlo:.3f}-{whi:.3f}) | {same}/{n} | {path} | {thr} |")
    table = "\n".join(lines)
    if a.queries:
        table += "\n\n" + queries_table(a)
    print(table)
    if a.out:
        cmd = " ".join([os.path.relpath(sys.argv[0], root)] + sys.argv[1:])
        pathlib.Path(a.out).write_text(
            f"# Scene.intersect (Python) against `arbor trace`\n\nModel `{pathlib.Path(a.model).name}`, "
            f"{a.rays} rays per kind, structure `{a.accel}`, {a.rounds} interleaved rounds, each a median of "
            f"{a.repeat}; arbor {arbor.__version__}, kernels {arbor.kernel_set()}.\n\n```sh\nPYTHONPATH=build/release/python "
            f"python3 {cmd}\n```\n\n{table}\n")


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
