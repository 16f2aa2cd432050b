#!/usr/bin/python3
"""arbor beside the libraries people cast rays with from Python, on the same meshes and queries:
Open3D's RaycastingScene (Debian python3-open3d), Embree 3 called directly (Debian libembree3,
through ctypes), fcpw when a checkout of it is given (--fcpw DIR or ARBOR_FCPW: a C++ shim of ours,
scripts/peers/fcpw_shim.cpp, is compiled against its headers and called through ctypes; without
one its column is left out and the report says why) and arbor's Python module. docs/benchmarks.md ("arbor beside its Python peers")
shows the current table and how to read it.

  /usr/bin/python3 scripts/bench_peers.py [--arbor build/release/apps/arbor/arbor]
      [--python-path build/release/python] [--models ../shared/scenes/models]
      [--scenes stanford-bunny,beast,rocker-arm,cheburashka] [--rays 262144] [--points 65536]
      [--rounds 5] [--threads 2] [--sample 300] [--fcpw FCPW_CHECKOUT] [--note TEXT]
      [-o build/results/peers.md]

Per model, every library builds its structure (timed apart, once per round) and answers, with the
same thread count, the queries of scripts/peers/queries.py: closest hit on camera, random and
edge-aimed rays; any hit on shadow rays; crossing counts on camera and random rays; closest-point
distance and inside on points in the box (inside only on closed meshes: elsewhere it is not
defined, and the row says it was skipped). Rounds interleave the libraries, the order rotated each
round; a figure is the median over rounds of one whole call (inputs prepared in each library's own
format beforehand, outputs as the library returns them). Ratio = the peer's median / arbor's: above
1, arbor is faster. Agreement: wherever two libraries' answers differ (up to --sample of them),
and on --sample queries more picked at random, the float64 referee (scripts/peers/referee.py)
says who is right; "wrong" counts a library's answers that differ from the referee's.
"""
import argparse
import os
import pathlib
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--arbor", default=str(ROOT / "build/release/apps/arbor/arbor"))
    ap.add_argument("--python-path", default=str(ROOT / "build/release/python"))
    ap.add_argument("--models", default=str(ROOT.parent / "shared/scenes/models"))
    ap.add_argument("--scenes", default="stanford-bunny,beast,rocker-arm,cheburashka")
    ap.add_argument("--rays", type=int, default=1 << 18)
    ap.add_argument("--points", type=int, default=1 << 16)
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--sample", type=int, default=300)
    ap.add_argument("--fcpw", default=os.environ.get("ARBOR_FCPW", ""),
                    help="an fcpw checkout (github.com/rohan-sawhney/fcpw); default $ARBOR_FCPW; none: no fcpw column")
    ap.add_argument("--note", default="", help="a line for the report's head, e.g. how loaded the machine was")
    ap.add_argument("-o", "--out", default=str(ROOT / "build/results/peers.md"))
    o = ap.parse_args()
    for path, what in ((o.arbor, "--arbor"), (o.models, "--models")):
        if not os.path.exists(path):
            sys.exit(f"bench_peers: {what} {path}: not found")
    sys.path.insert(0, o.python_path)
    sys.path.insert(0, str(ROOT / "scripts"))
    from peers.shim import open3d_with_mask_shim
    open3d_with_mask_shim("bench_peers")
    from peers.compare import run_model
    from peers.fcpw_peer import compile_shim
    o.fcpw_shim, o.fcpw_missing = None, ""
    if not o.fcpw:
        o.fcpw_missing = "no fcpw checkout given (--fcpw DIR or ARBOR_FCPW)"
    else:
        try:
            o.fcpw_shim = compile_shim(o.fcpw)
        except RuntimeError as e:
            sys.exit(f"bench_peers: {e}")
    if o.fcpw_missing:
        print(f"bench_peers: fcpw left out: {o.fcpw_missing}", flush=True)
    from peers.report import write_report

    results = []
    for name in o.scenes.split(","):
        print(f"== {name}", flush=True)
        results.append(run_model(os.path.join(o.models, name + ".obj"), name, o))
    write_report(results, o)


if __name__ == "__main__":
    main()
