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
  - `arbor trace --threads T --repeat R --json`: the achieved rays/s (median) on the default path.

The model, per ray:
  compute (hot caches) = node_tests x t_node + blocks x t_block        (one thread)
  bytes (cold, an upper bound on traffic) = node_tests x node_bytes + blocks x block_bytes
  memory = bytes / bandwidth of the level that holds the layout: the last-level cache when the
           layout fits in the cache buffer measured (--cache-mib of `limit kernels`), else memory
  limit rays/s = T / max(compute, memory)
i.e. the roofline: the two overlap at best (the walk prefetches a node's children while it tests
the next), so the slower of the two bounds the rate; their sum would be the bound with no
overlap. Beside it: the bound if every byte came from memory (DRAM), and the compute bound with
chained node tests (each node test waits for the last, as in one ray's walk).
fraction = achieved / limit. A missing counter or field is an error (exit 1), never a zero.
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
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--rays-dir", default=os.path.join(root, "build", "rays-limit"))
    a = ap.parse_args()
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
    bw = need(machine, "bandwidth", "limit kernels")
    suffix = "2_threads" if a.threads == 2 else "1_thread"
    dram = need(bw, "gbs_" + suffix, "bandwidth") * 1e9
    cache = need(bw, "cache_gbs_" + suffix, "bandwidth") * 1e9
    cache_bytes = need(bw, "cache_mib", "bandwidth") * 1024 * 1024

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
                t = run_json([arbor, "trace", "--scene", model, "--rays", rays, "--accel", s, "--threads", str(a.threads),
                              "--repeat", str(a.repeat), "--json", *occ], env)
                what = f"limit count {stem} {kind} {s}"
                width = need(c, "width", what)
                if width not in kernels:
                    fail(f"no kernel time of width {width} (kernels measured: {sorted(kernels)})")
                k = kernels[width]
                nodes = need(c, "node_tests_per_ray", what)
                blocks = need(c, "blocks_per_ray", what)
                tris = need(c, "triangles_per_ray", what)
                if need(c, "rays", what) != a.rays or nodes <= 0:
                    fail(f"{what}: implausible counts {c}")
                compute_ns = nodes * need(k, "node_ns", "kernels") + blocks * need(k, "block_ns", "kernels")
                serial_ns = nodes * need(k, "node_chain_ns", "kernels") + blocks * need(k, "block_ns", "kernels")
                traffic = nodes * need(c, "node_bytes", what) + blocks * need(c, "block_bytes", what)
                resident = need(c, "layout_bytes", what) <= cache_bytes
                compute_limit = a.threads / (compute_ns * 1e-9)
                memory_limit = (cache if resident else dram) / traffic
                dram_limit = dram / traffic
                serial_limit = a.threads / (serial_ns * 1e-9)
                limit = min(compute_limit, memory_limit)
                achieved = need(t, "mrays_per_s", f"arbor trace {stem} {kind} {s}") * 1e6
                rows.append(dict(model=stem, kind=kind, structure=s, path=need(t, "path", "arbor trace"), width=width,
                                 nodes=nodes, blocks=blocks, tris=tris, compute_ns=compute_ns, serial_ns=serial_ns,
                                 traffic=traffic, layout_mib=c["layout_bytes"] / 2**20,
                                 compute_limit=compute_limit, memory_limit=memory_limit, limit=limit,
                                 bound="compute" if compute_limit <= memory_limit else ("cache" if resident else "memory"),
                                 achieved=achieved, fraction=achieved / limit, dram_fraction=achieved / dram_limit,
                                 serial_fraction=achieved / serial_limit))
                r = rows[-1]
                print(f"{stem} {kind} {s}: {nodes:.1f} nodes {blocks:.2f} blocks, limit {limit / 1e6:.1f} Mrays/s "
                      f"({r['bound']}), achieved {achieved / 1e6:.2f} ({r['fraction']:.2f})", file=sys.stderr)
    load_after = loadavg()

    git = subprocess.run(["git", "-C", root, "rev-parse", "--short", "HEAD"], capture_output=True, text=True).stdout.strip()
    cpu = next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name")), "?")
    out = []
    out.append(f"# Distance to the limit ({date.today().isoformat()}, loaded)\n")
    out.append(f"- machine: {cpu}, {os.cpu_count()} hardware threads, shared with other builds (loaded); "
               f"load average before {load_before}, after {load_after}; git {git}")
    out.append(f"- command: `scripts/limit_model.py` ({a.rays} rays per file, `arbor rays --scene MODEL --kind KIND "
               f"--count {a.rays}` with the recipes of scripts/bench_heldout.sh; achieved: `arbor trace --threads "
               f"{a.threads} --repeat {a.repeat}`, median, default path)")
    out.append(f"- TSC {machine['tsc_ghz']:.3f} GHz (cycles below are TSC cycles: the VM has no core cycle counter)")
    out.append("")
    out.append("Kernels with hot caches (loaded; best of 101 timings, median in brackets; independent tests back to back; "
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
    out.append(f"Streaming read (loaded): memory ({bw['buffer_mib']} MiB, best of 15) {bw['gbs_1_thread']:.1f} GB/s on 1 thread, "
               f"{bw['gbs_2_threads']:.1f} GB/s on 2; last-level cache ({bw['cache_mib']} MiB, best of 101) "
               f"{bw['cache_gbs_1_thread']:.1f} GB/s on 1 thread, {bw['cache_gbs_2_threads']:.1f} GB/s on 2.\n")
    out.append(f"Per ray, {a.threads} threads (loaded). nodes, blocks, tris: per ray, of the counted single-ray walk "
               "(wide node tests, triangle blocks tested, the triangles in them); layout: MiB of the wide layout; "
               "compute: ns per ray with hot caches (1 thread); bytes: node and block bytes per ray (cold traffic, an "
               "upper bound); limit: the roofline min(compute rate, bytes rate of the level that holds the layout), "
               "bound: which; achieved: `arbor trace`, on its default path; fraction = achieved / limit; "
               "of DRAM: achieved / (memory bandwidth / bytes), every byte from memory; chained: achieved / the "
               "compute rate with chained node tests.\n")
    out.append("| model | kind | structure | path | nodes | blocks | tris | layout MiB | compute ns | bytes | compute Mrays/s | bytes Mrays/s | limit Mrays/s | achieved Mrays/s | fraction | of DRAM | chained |")
    out.append("|---|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    for r in rows:
        out.append(f"| {r['model']} | {r['kind']} | {r['structure']} | {r['path']} | {r['nodes']:.1f} | {r['blocks']:.2f} | "
                   f"{r['tris']:.1f} | {r['layout_mib']:.1f} | {r['compute_ns']:.1f} | {r['traffic']:.0f} | "
                   f"{r['compute_limit'] / 1e6:.0f} | {r['memory_limit'] / 1e6:.0f} | {r['limit'] / 1e6:.0f} ({r['bound']}) | "
                   f"{r['achieved'] / 1e6:.2f} | {r['fraction']:.3f} | {r['dram_fraction']:.2f} | {r['serial_fraction']:.2f} |")
    os.makedirs(os.path.dirname(os.path.abspath(a.out)), exist_ok=True)
    with open(a.out, "w") as f:
        f.write("\n".join(out) + "\n")
    print(f"report: {a.out}")


if __name__ == "__main__":
    main()
