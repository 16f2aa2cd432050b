#!/usr/bin/python3
"""Distance to the limit (docs/benchmarks.md): per model, ray kind and structure, the best this
machine could do by a simple model beside the rays/s arbor achieves on the same rays.

    scripts/limit_model.py [-o perf/results/limit.md] [--models A.obj,B.obj] [--kinds ...]
                           [--structures ...] [--rays N] [--threads 2] [--repeat 5]

Inputs, all measured in the one run:
  - `arbor-bench limit kernels`: one N-wide node test (t_node) and one N-wide triangle block test
    (t_block) with hot caches (best of 101, ns), the streaming read bandwidth at 1 and 2 threads, and
    the bytes of a node (with its order row) and of a block;
  - `arbor-bench limit count`: node tests, blocks and triangles per ray of the counted single-ray
    walk of the structure's N-wide layout (the path trace_single walks; hits checked bit for bit
    against TracePath::single's);
  - `arbor trace --threads T --repeat R --json`: the achieved rays/s (best repeat) on the default path,
    and again with `--path single` (the walk the counts are of: the default path of coherent
    kinds is the packet walk, which tests a node once for up to 16 rays).

The model, per ray:
  compute (hot caches) = node_tests x t_node + blocks x t_block        (one thread)
  limit rays/s = T / compute: no walk that makes these tests can go faster than its tests back
           to back with every byte in L1, so this bounds the rate from above.
  bytes (cold) = node_tests x node_bytes + blocks x block_bytes: every line of every node and block
           a ray tests, as if each were fetched for that ray alone; rays share lines (the top of
           the tree, neighbours' nodes, a packet's fetches), so the traffic is at most this, and
  cold rate = bandwidth / bytes, from the level that holds the layout (the last-level cache when
           it fits in the cache buffer measured, --cache-mib of `limit kernels`, else memory), is
           the rate if no line were shared: not a bound (achieved rates above it show reuse).
fraction = achieved / limit; beside it achieved / cold rate (above 1: rays reuse lines), the same
from memory (DRAM), and achieved / the compute rate with chained node tests (each node test waits
for the last, as in one ray's walk). A missing counter or field is an error (exit 1), never a zero.
"""
import argparse
import json
import os
import subprocess
import sys
from datetime import date

KINDS = {
    "primary": (["--kind", "primary"], False),
    "shadow": (["--kind", "shadow"], True),
    "shadow-area": (["--kind", "shadow", "--light-size", "0.5"], True),
    "shadow-near": (["--kind", "shadow", "--light-distance", "0.6"], True),
    "shadow-all": (["--kind", "shadow", "--from", "all"], True),
    "diffuse": (["--kind", "diffuse"], False),
    "random": (["--kind", "random"], False),
}


def fail(msg):
    print(f"limit_model.py: {msg}", file=sys.stderr)
    sys.exit(1)


def need(obj, key, what):
    """obj[key], or a loud failure naming the missing counter."""
    if key not in obj or obj[key] is None:
        fail(f"missing counter '{key}' in {what}: {json.dumps(obj)[:300]}")
    return obj[key]


def run_json(cmd, env=None):
    p = subprocess.run(cmd, capture_output=True, text=True, env=env)
    if p.returncode != 0:
        fail(f"{' '.join(cmd)} exited {p.returncode}: {p.stderr.strip()}")
    lines = [l for l in p.stdout.splitlines() if l.startswith("{")]
    if not lines:
        fail(f"{' '.join(cmd)}: no JSON on standard output")
    return json.loads(lines[-1])


def model_row(c, t, t1, kernels, bw, threads, what):
    """The model of one (model, kind, structure): `c` the counts (`limit count`), `t` and `t1` the
    `arbor trace` JSON of the default and the single path, `kernels` the kernel times by width and
    `bw` the bandwidths (`limit kernels`)."""
    width = need(c, "width", "limit count " + what)
    if width not in kernels:
        fail(f"no kernel time of width {width} (kernels measured: {sorted(kernels)})")
    k = kernels[width]
    nodes = need(c, "node_tests_per_ray", "limit count " + what)
    blocks = need(c, "blocks_per_ray", "limit count " + what)
    tris = need(c, "triangles_per_ray", "limit count " + what)
    if nodes <= 0 or not blocks * width >= tris >= blocks:
        fail(f"limit count {what}: implausible counts {c}")
    suffix = "2_threads" if threads == 2 else "1_thread"
    dram = need(bw, "gbs_" + suffix, "bandwidth") * 1e9
    cache = need(bw, "cache_gbs_" + suffix, "bandwidth") * 1e9
    compute_ns = nodes * need(k, "node_ns", "kernels") + blocks * need(k, "block_ns", "kernels")
    serial_ns = nodes * need(k, "node_chain_ns", "kernels") + blocks * need(k, "block_ns", "kernels")
    traffic = nodes * need(c, "node_bytes", "limit count " + what) + blocks * need(c, "block_bytes", "limit count " + what)
    layout = need(c, "layout_bytes", "limit count " + what)
    resident = layout <= need(bw, "cache_mib", "bandwidth") * 2**20
    compute_limit = threads / (compute_ns * 1e-9)
    memory_limit = (cache if resident else dram) / traffic  # the cold rate: not a bound (see above)
    limit = compute_limit
    # The best of the repeats (the limit's kernel times and bandwidths are bests too: on a loaded
    # machine the best run is the one least disturbed), the median beside it.
    achieved = need(t, "rays", "arbor trace " + what) / need(t, "trace_ms_min", "arbor trace " + what) * 1e3
    single = need(t1, "rays", "arbor trace --path single " + what) / need(t1, "trace_ms_min", "arbor trace --path single " + what) * 1e3
    median = need(t, "mrays_per_s", "arbor trace " + what) * 1e6
    return dict(rays=need(c, "rays", "limit count " + what), path=need(t, "path", "arbor trace " + what), width=width,
                nodes=nodes, blocks=blocks, tris=tris, compute_ns=compute_ns, serial_ns=serial_ns, traffic=traffic,
                layout_mib=layout / 2**20, compute_limit=compute_limit, memory_limit=memory_limit, limit=limit,
                level="cache" if resident else "memory", achieved=achieved, median=median, fraction=achieved / limit,
                single=single, single_fraction=single / limit, cold_fraction=achieved / memory_limit,
                dram_fraction=achieved / (dram / traffic), serial_fraction=achieved / (threads / (serial_ns * 1e-9)))


def compact_table(rows):
    """The table docs/benchmarks.md quotes: per model, kind and structure the counts, the limit and
    the fractions achieved on the default and the single path."""
    out = ["The same, short (the table docs/benchmarks.md quotes):\n",
           "| model | kind | structure | nodes | blocks | limit Mrays/s | default path: Mrays/s | fraction | single: Mrays/s | fraction | bytes | achieved / cold rate |",
           "|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for r in rows:
        out.append(f"| {r['model']} | {r['kind']} | {r['structure']} | {r['nodes']:.1f} | {r['blocks']:.2f} | "
                   f"{r['limit'] / 1e6:.0f} | {r['achieved'] / 1e6:.1f} ({r['path']}) | "
                   f"{r['fraction']:.2f} | {r['single'] / 1e6:.1f} | {r['single_fraction']:.2f} | {r['traffic']:.0f} | "
                   f"{r['cold_fraction']:.2f} ({r['level']}) |")
    return "\n".join(out)


def self_test():
    """The model on made-up inputs, and a missing counter refused (exit 1)."""
    kernels = {16: dict(node_ns=2.0, block_ns=8.0, node_chain_ns=10.0)}
    bw = dict(gbs_2_threads=20.0, gbs_1_thread=20.0, cache_gbs_2_threads=50.0, cache_gbs_1_thread=50.0, cache_mib=8)
    c = dict(width=16, rays=100, node_tests_per_ray=4.0, blocks_per_ray=2.0, triangles_per_ray=20.0, node_bytes=528,
             block_bytes=640, layout_bytes=4 * 2**20)
    r = model_row(c, dict(mrays_per_s=9.0, rays=100, trace_ms_min=1e-2, path="packet"), dict(rays=100, trace_ms_min=2e-2),
                  kernels, bw, 2, "self-test")
    # compute 4 x 2 + 2 x 8 = 24 ns: limit 2 / 24 ns; bytes 4 x 528 + 2 x 640 = 3392 from the cache:
    # cold rate 50e9 / 3392 rays/s; achieved 100 rays in 0.01 ms = 10e6 rays/s
    ok = abs(r["compute_ns"] - 24.0) < 1e-9 and r["traffic"] == 3392 and r["level"] == "cache"
    ok = ok and abs(r["limit"] - 2 / 24e-9) < 1.0 and abs(r["fraction"] - 10e6 / (2 / 24e-9)) < 1e-9
    ok = ok and abs(r["cold_fraction"] - 10e6 / (50e9 / 3392)) < 1e-9
    c_big = dict(c, layout_bytes=64 * 2**20)
    t = dict(mrays_per_s=1, rays=1, trace_ms_min=1, path="single")
    big = model_row(c_big, t, t, kernels, bw, 2, "big")
    ok = ok and big["level"] == "memory" and abs(big["memory_limit"] - 20e9 / 3392) < 1.0
    if not ok:
        print(f"self-test: the model computed {r}", file=sys.stderr)
        return 1
    for broken in ({k: v for k, v in c.items() if k != "blocks_per_ray"}, dict(c, node_tests_per_ray=None)):
        p = subprocess.run([sys.executable, "-c", "import sys; sys.path.insert(0, sys.argv[1]); import limit_model as m; "
                            "m.model_row(" + repr(broken) + ", " + repr(t) + ", " + repr(t) + ", "
                            + repr(kernels) + ", " + repr(bw) + ", 2, 'x')", os.path.dirname(os.path.abspath(__file__))],
                           capture_output=True, text=True)
        if p.returncode != 1 or "missing counter" not in p.stderr:
            print(f"self-test: a missing counter was not refused (exit {p.returncode}): {p.stderr}", file=sys.stderr)
            return 1
    print("self-test: passed")
    return 0


def shared_scenes_of(build):
    """The ARBOR_SHARED_SCENES the build was configured with (its CMakeCache.txt), or None."""
    try:
        for line in open(os.path.join(build, "CMakeCache.txt")):
            if line.startswith("ARBOR_SHARED_SCENES:"):
                return line.split("=", 1)[1].strip()
    except OSError:
        pass
    return None


def loadavg():
    return "%.2f %.2f %.2f" % os.getloadavg()


def main():
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    shared = os.environ.get("ARBOR_SHARED_SCENES") or shared_scenes_of(os.path.join(root, "build", "release")) or \
        os.path.join(os.path.dirname(root), "shared", "scenes")
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("-o", "--out", default=os.path.join(root, "perf", "results", "limit.md"))
    ap.add_argument("--build", default=os.path.join(root, "build", "release"))
    ap.add_argument("--models", default=",".join(os.path.join(shared, "models", m) for m in ("stanford-bunny.obj", "beast.obj")))
    ap.add_argument("--kinds", default=",".join(KINDS))
    ap.add_argument("--structures", default="bvh-sah,lbvh,kdtree,bvh-median")
    ap.add_argument("--rays", type=int, default=131072)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--repeat", type=int, default=7)
    ap.add_argument("--rays-dir", default=os.path.join(root, "build", "rays-limit"))
    ap.add_argument("--self-test", action="store_true", help="check the model's arithmetic and its refusals, then exit")
    a = ap.parse_args()
    if a.self_test:
        sys.exit(self_test())
    kinds = a.kinds.split(",")
    for k in kinds:
        if k not in KINDS:
            print(f"limit_model.py: --kinds: unknown kind '{k}' (expected {', '.join(KINDS)})", file=sys.stderr)
            sys.exit(2)
    if a.threads not in (1, 2):
        print("limit_model.py: --threads: 1 or 2 (the bandwidth is measured at 1 and 2 threads)", file=sys.stderr)
        sys.exit(2)
    arbor = os.path.join(a.build, "apps", "arbor", "arbor")
    bench = os.path.join(a.build, "perf", "arbor-bench")
    for exe in (arbor, bench):
        if not os.access(exe, os.X_OK):
            fail(f"{exe} not built (cmake --build {a.build} --target arbor arbor-bench)")
    env = dict(os.environ, ARBOR_SHARED_SCENES=shared)
    os.makedirs(a.rays_dir, exist_ok=True)

    load_before = loadavg()
    machine = run_json([bench, "limit", "kernels"])
    kernels = {need(k, "width", "kernels"): k for k in need(machine, "kernels", "limit kernels")}
    bytes_by_width = {need(b, "width", "bytes"): b for b in need(machine, "bytes", "limit kernels")}
    bw = machine_bw = need(machine, "bandwidth", "limit kernels")

    rows = []
    for model in a.models.split(","):
        stem = os.path.splitext(os.path.basename(model))[0]
        for kind in kinds:
            make, occluded = KINDS[kind]
            rays = os.path.join(a.rays_dir, f"{stem}-{kind}-{a.rays}.rays")
            if not os.path.exists(rays):
                run_json([arbor, "rays", "--scene", model, *make, "--count", str(a.rays), "-o", rays, "--json"], env)
            for s in a.structures.split(","):
                occ = ["--occluded"] if occluded else []
                c = run_json([bench, "limit", "count", "--scene", model, "--rays", rays, "--accel", s, *occ], env)
                trace = [arbor, "trace", "--scene", model, "--rays", rays, "--accel", s, "--threads", str(a.threads),
                         "--repeat", str(a.repeat), "--json", *occ]
                t = run_json(trace, env)
                t1 = run_json(trace + ["--path", "single"], env)  # the path the counts are of
                what = f"{stem} {kind} {s}"
                rows.append(model_row(c, t, t1, kernels, machine_bw, a.threads, what))
                rows[-1].update(model=stem, kind=kind, structure=s)
                if rows[-1]["rays"] != a.rays:
                    fail(f"limit count {what}: {rows[-1]['rays']} rays counted, the file holds {a.rays}")
                r = rows[-1]
                print(f"{what}: {r['nodes']:.1f} nodes {r['blocks']:.2f} blocks, limit {r['limit'] / 1e6:.1f} Mrays/s, "
                      f"achieved {r['achieved'] / 1e6:.2f} ({r['fraction']:.2f}; {r['cold_fraction']:.2f} of the cold rate)",
                      file=sys.stderr)
    load_after = loadavg()

    git = subprocess.run(["git", "-C", root, "rev-parse", "--short", "HEAD"], capture_output=True, text=True).stdout.strip()
    cpu = next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name")), "?")
    # Quiet when the load average before and after stayed below 2 on the 2 threads (only the run's own).
    state = "quiet" if max(float(load_before.split()[0]), float(load_after.split()[0])) < 2.0 else "loaded"
    out = []
    out.append(f"# Distance to the limit ({date.today().isoformat()}, {state})\n")
    out.append(f"- machine: {cpu}, {os.cpu_count()} hardware threads ({state}); "
               f"load average before {load_before}, after {load_after}; git {git}")
    out.append(f"- command: `scripts/limit_model.py` ({a.rays} rays per file, `arbor rays --scene MODEL --kind KIND "
               f"--count {a.rays}` with the recipes of scripts/bench_heldout.sh; achieved: `arbor trace --threads "
               f"{a.threads} --repeat {a.repeat}`, the best repeat (rays / trace_ms_min), on the default path and on `--path single`)")
    out.append(f"- TSC {machine['tsc_ghz']:.3f} GHz (cycles below are TSC cycles: the VM has no core cycle counter)")
    out.append("")
    out.append(f"Kernels with hot caches ({state}; best of 101 timings, median in brackets; independent tests back to back; "
               "`chain`: each node test chosen by the last one's outcome, as in one ray's walk):\n")
    out.append("| width | node test ns (TSC cycles) | chained node test ns | block test ns (TSC cycles) | node + order row bytes | block bytes | lanes checked against the scalar oracles |")
    out.append("|---:|---:|---:|---:|---:|---:|---:|")
    for w in sorted(kernels, reverse=True):
        k, b = kernels[w], bytes_by_width[w]
        out.append(f"| {w} | {k['node_ns']:.2f} [{k['node_ns_median']:.2f}] ({k['node_tsc_cycles']:.1f}) | "
                   f"{k['node_chain_ns']:.2f} [{k['node_chain_ns_median']:.2f}] | "
                   f"{k['block_ns']:.2f} [{k['block_ns_median']:.2f}] ({k['block_tsc_cycles']:.1f}) | "
                   f"{b['node'] + b['node_order_row']} | {b['block']} | {k['checked_lanes']} |")
    out.append("")
    out.append(f"Streaming read ({state}): memory ({bw['buffer_mib']} MiB, best of 15) {bw['gbs_1_thread']:.1f} GB/s on 1 thread, "
               f"{bw['gbs_2_threads']:.1f} GB/s on 2; last-level cache ({bw['cache_mib']} MiB, read 16 times, best of 51) "
               f"{bw['cache_gbs_1_thread']:.1f} GB/s on 1 thread, {bw['cache_gbs_2_threads']:.1f} GB/s on 2.\n")
    out.append(f"Per ray, {a.threads} threads ({state}). nodes, blocks, tris: per ray, of the counted single-ray walk "
               "(wide node tests, triangle blocks tested, the triangles in them); layout: MiB of the wide layout; "
               "compute: ns per ray with hot caches (1 thread); limit: the compute rate on the run's threads (an upper "
               "bound); bytes: node and block bytes per ray, every line as if fetched for that ray alone; cold rate: "
               "the bandwidth of the level that holds the layout / bytes (the rate with no line shared between rays: "
               "not a bound); achieved: `arbor trace`, best repeat, on its default path (`path`: the one it took; "
               "median: the median repeat); fraction = achieved / limit; single: `arbor trace --path single`, the "
               "path the counts are of, and its fraction; of cold: achieved / cold rate (above 1: rays reuse lines); "
               "of DRAM: the same with every byte from memory; chained: achieved / the compute rate with chained "
               "node tests.\n")
    out.append("| model | kind | structure | path | nodes | blocks | tris | layout MiB | compute ns | bytes | limit Mrays/s | cold rate Mrays/s | achieved Mrays/s | median | fraction | single Mrays/s | single fraction | of cold | of DRAM | chained |")
    out.append("|---|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for r in rows:
        out.append(f"| {r['model']} | {r['kind']} | {r['structure']} | {r['path']} | {r['nodes']:.1f} | {r['blocks']:.2f} | "
                   f"{r['tris']:.1f} | {r['layout_mib']:.1f} | {r['compute_ns']:.1f} | {r['traffic']:.0f} | "
                   f"{r['limit'] / 1e6:.0f} | {r['memory_limit'] / 1e6:.0f} ({r['level']}) | "
                   f"{r['achieved'] / 1e6:.2f} | {r['median'] / 1e6:.2f} | {r['fraction']:.2f} | {r['single'] / 1e6:.2f} | {r['single_fraction']:.2f} | "
                   f"{r['cold_fraction']:.2f} | {r['dram_fraction']:.2f} | {r['serial_fraction']:.2f} |")
    out.append("")
    out.append(compact_table(rows))
    os.makedirs(os.path.dirname(os.path.abspath(a.out)), exist_ok=True)
    with open(a.out + ".tmp", "w") as f:
        f.write("\n".join(out) + "\n")
    os.replace(a.out + ".tmp", a.out)
    print(f"report: {a.out}")


if __name__ == "__main__":
    main()
