#!/usr/bin/env bash
# Builds as a user meets them: one build in a fresh process (cold allocator, page tables and thread
# pool), arbor's lbvh and bvh-sah (the SIMD-layout build `arbor trace` makes for its default path:
# the same make_accel call, in `arbor-bench build-once`) against Embree's default build (rtcCommitScene) in
# its own fresh process, interleaved (the order rotated each round), 2 threads:
#   [ROUNDS=5] [SCENES="builtin:scaling:3 builtin:scaling:8"] scripts/bench_fresh_build.sh [OUT.md]
# Reports per scene the median build ms (wall), the median of the per-round ratios to Embree, the
# CPU ms and page faults of the build, arbor's SAH cost, and trace speed of each tree on 131072
# primary rays (`arbor trace --repeat 5`, default path). builtin:scaling:N is N x N Stanford bunnies
# on a ground plane (N=3: 0.63M, N=8: 4.4M triangles).
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-build/results/fresh-build-$(date +%Y-%m-%d).md}
mkdir -p "$(dirname "$out")"
rounds=${ROUNDS:-5}
scenes=${SCENES:-"builtin:scaling:3 builtin:scaling:8"}
cmake --preset release >/dev/null
cmake --build --preset release -j2 --target arbor arbor-bench >/dev/null
arbor=build/release/apps/arbor/arbor
once="build/release/perf/arbor-bench build-once"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
load0=$(cut -d' ' -f1-3 /proc/loadavg)
for scene in $scenes; do
  s=${scene//:/-}
  for r in $(seq 1 "$rounds"); do
    set -- lbvh bvh-sah embree
    for k in $(seq 2 "$r"); do set -- "$2" "$3" "$1"; done  # rotate the order each round
    for w in "$@"; do $once --scene "$scene" --with "$w" --threads 2 | sed "s/^{/{\"round\":$r,/" >>"$tmp/$s.jsonl"; done
  done
  $arbor rays --scene "$scene" --kind primary --count 131072 -o "$tmp/$s.rays" >/dev/null
  for w in lbvh bvh-sah; do
    $arbor trace --scene "$scene" --rays "$tmp/$s.rays" --accel $w --threads 2 --repeat 5 --json >>"$tmp/$s-trace.jsonl"
  done
done
/usr/bin/python3 - "$tmp" "$rounds" "$load0" "$(cut -d' ' -f1-3 /proc/loadavg)" "$(git rev-parse --short HEAD)" $scenes >"$out.tmp" <<'PY'
import json, statistics as st, sys, glob, os
tmp, rounds, load0, load1, git = sys.argv[1:6]
scenes = sys.argv[6:]
print(f"# Fresh-process builds against Embree (git {git})\n")
print(f"- one build per fresh process (`arbor-bench build-once`: make_accel with the SIMD layouts only, as `arbor trace` on its default path; "
      f"Embree 3 default MEDIUM build, rtcCommitScene), 2 threads, {rounds} rounds, order rotated each round")
print(f"- load average {load0} at the start, {load1} at the end (the machine is shared: other engineers compile)")
print("- ratio = median over the rounds of (arbor ms / Embree ms in the same round); cpu = user+sys ms of the build "
      "(Embree's includes its device and buffer setup); faults = minor page faults during the build\n")
print("| scene | triangles | builder | build ms (median, wall) | x Embree (wall) | cpu ms | x Embree (cpu) | faults | SAH cost | trace Mrays/s (primary) |")
print("|---|---:|---|---:|---:|---:|---:|---:|---:|---:|")
for scene in scenes:
    s = scene.replace(":", "-")
    rows = [json.loads(l) for l in open(f"{tmp}/{s}.jsonl")]
    trace = {j["accel"]: j for j in map(json.loads, open(f"{tmp}/{s}-trace.jsonl"))}
    by = lambda w: {r["round"]: r for r in rows if r["with"] == w}
    emb = by("embree")
    for w in ["lbvh", "bvh-sah", "embree"]:
        b = by(w)
        ms = st.median(r["build_ms"] for r in b.values())
        cpu = st.median(r["cpu_ms"] for r in b.values())
        flt = st.median(r["minor_faults"] for r in b.values())
        rw = st.median(b[k]["build_ms"] / emb[k]["build_ms"] for k in b)
        rc = st.median(b[k]["cpu_ms"] / emb[k]["cpu_ms"] for k in b)
        tri = next(iter(b.values()))["triangles"]
        sah = f'{next(iter(b.values()))["sah_cost"]:.2f}' if w != "embree" else "-"
        tr = f'{trace[w]["mrays_per_s"]:.2f}' if w in trace else "-"
        print(f"| {scene} | {tri} | {w} | {ms:.0f} [{min(r['build_ms'] for r in b.values()):.0f}-{max(r['build_ms'] for r in b.values()):.0f}] | **{rw:.2f}** | {cpu:.0f} | {rc:.2f} | {flt:.0f} | {sah} | {tr} |")
PY
mv "$out.tmp" "$out"
cat "$out"
