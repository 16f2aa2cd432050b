#!/bin/bash
# Trace speed, build time and memory of the BVHs' SIMD paths for values of --simd-leaf-floor, runs
# interleaved per round (A B C A B C ...). Usage:
#   scripts/bench_leaf_floor.sh [ROUNDS] [ACCEL] [FLOOR...]     (defaults: 3 bvh-sah 16 8 1)
# Rays: 500k each of primary, shadow, diffuse and random on the bunny, beast and rocker arm. Each
# run reports the median of 5 traces; the table gives, per case, the median over rounds of the
# per-round ratio to the last floor given (1 = the fine tree).
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
arbor="$here/build/release/apps/arbor/arbor"
models="$here/../shared/scenes/models"
rounds="${1:-3}"; accel="${2:-bvh-sah}"; shift $(( $# >= 2 ? 2 : $# ))
floors=("$@"); [ ${#floors[@]} -gt 0 ] || floors=(16 8 1)
tmp="$(mktemp -d)"; trap 'rm -rf "$tmp"' EXIT
for s in stanford-bunny beast rocker-arm; do
  for k in primary shadow diffuse random; do
    "$arbor" rays --scene "$models/$s.obj" --kind $k --count 500000 -o "$tmp/${s}_$k.rays" > /dev/null
  done
done
for s in stanford-bunny beast rocker-arm; do for k in primary shadow diffuse random; do
  q=""; [ $k = shadow ] && q="--occluded"
  for p in single packet; do for r in $(seq "$rounds"); do for v in "${floors[@]}"; do
    "$arbor" trace --scene "$models/$s.obj" --rays "$tmp/${s}_$k.rays" --accel "$accel" --path $p $q \
      --simd-leaf-floor "$v" --repeat 5 --json 2> /dev/null |
      python3 -c "import json,sys; d=json.load(sys.stdin); print('$s $k $p $v', d['trace_ms'], d['build_ms'], d['memory_bytes'])"
  done; done; done
done; done > "$tmp/runs.txt"
python3 - "$tmp/runs.txt" <<'PY'
import sys, statistics as st, collections
rows = collections.defaultdict(lambda: collections.defaultdict(list)); order = []
for line in open(sys.argv[1]):
    p = line.split()
    rows[tuple(p[:3])][p[3]].append((float(p[4]), float(p[5]), int(p[6])))
    if p[3] not in order: order.append(p[3])
base = order[-1]
hdr = ("| scene | rays | path | " + " | ".join(f"trace ms, floor {v}" for v in order) + " | " +
       " | ".join(f"floor {v} / {base}" for v in order[:-1]) + " | build ms " + " / ".join(order) +
       " | memory MB " + " / ".join(order) + " |")
print(hdr); print("|" + "---|" * (hdr.count("|") - 1))
ratios = collections.defaultdict(list); builds = collections.defaultdict(list)
for key, v in rows.items():
    meds = [st.median([x[0] for x in v[o]]) for o in order]
    rr = []
    for o in order[:-1]:
        r = st.median([x[0] / y[0] for x, y in zip(v[o], v[base])]); rr.append(r); ratios[o].append(r)
        builds[o].append(st.median([x[1] / y[1] for x, y in zip(v[o], v[base])]))
    b = [st.median([x[1] for x in v[o]]) for o in order]
    m = [v[o][0][2] / 1e6 for o in order]
    print(f"| {key[0]} | {key[1]} | {key[2]} | " + " | ".join(f"{x:.1f}" for x in meds) + " | " +
          " | ".join(f"{x:.3f}" for x in rr) + " | " + " / ".join(f"{x:.1f}" for x in b) + " | " +
          " / ".join(f"{x:.2f}" for x in m) + " |")
print()
for o in order[:-1]:
    r = ratios[o]
    print(f"floor {o} / floor {base}: trace time, median of the {len(r)} per-case ratios {st.median(r):.3f} "
          f"(min {min(r):.3f}, max {max(r):.3f}); build time {st.median(builds[o]):.3f}")
PY
