#!/usr/bin/env bash
# arbor against Embree on identical .rays files, in one run (docs/benchmarks.md, "Tuning rays against Embree"):
#   [REPEATS=5] [MIN_MS=40] scripts/bench_vs_embree.sh [OUT.md] [arbor-bench paths options...]
# Builds the release preset, writes the ray files of the bunny, the beast and the rocker arm with
# `arbor rays` (primary, shadow, diffuse, random; RAYS rays each, seed 1, tile order) into
# $ARBOR_RAYS_DIR (default build/rays), then runs `arbor-bench paths`: every BVH structure and the kd-tree,
# every traversal path, Embree's rtcIntersect1/8/16/1M, 2 threads, median of 5, round-robin; each
# timed sample repeats the file's pass for at least MIN_MS ms (a pass of primary rays lasts ~3 ms).
# The table goes to OUT.md (default build/results/vs-embree-DATE.md).
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-build/results/vs-embree-$(date +%Y-%m-%d).md}
[ $# -gt 0 ] && shift
rays=${RAYS:-131072}
dir=${ARBOR_RAYS_DIR:-build/rays}
models=${ARBOR_MODELS:-../shared/scenes/models}
mkdir -p "$dir" "$(dirname "$out")"

cmake --preset release >/dev/null
cmake --build --preset release -j2 --target arbor arbor-bench >/dev/null

for scene in stanford-bunny beast rocker-arm; do
  for kind in primary shadow diffuse random; do
    f="$dir/$scene-$kind.rays"
    [ -f "$f" ] || build/release/apps/arbor/arbor rays --scene "$models/$scene.obj" --kind $kind --count "$rays" -o "$f" >/dev/null
  done
done

{
  echo "# arbor vs Embree on identical ray files ($(date +%Y-%m-%d))"
  echo
  echo "- machine: $(lscpu | sed -n 's/^Model name:\s*//p'), $(nproc) hardware threads; $(c++ --version | head -1); git $(git rev-parse --short HEAD 2>/dev/null || echo '?')"
  echo "- rays: $rays per file, written by \`arbor rays --scene MODEL.obj --kind KIND --count $rays\` (seed 1, 8x8 tile order)"
  build/release/perf/arbor-bench paths --rays "$dir" --models "$models" --structures bvh-median,bvh-sah,lbvh,kdtree \
    --paths scalar,single,packet,best --threads 2 --repeats "${REPEATS:-5}" --min-ms "${MIN_MS:-40}" "$@"
} >"$out"
echo "report: $out"
