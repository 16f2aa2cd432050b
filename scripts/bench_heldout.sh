#!/usr/bin/env bash
# arbor against Embree on HELD-OUT rays: rays the benchmark files were never tuned on
# (docs/benchmarks.md, "Held-out rays against Embree"):
#   [REPEATS=5] [MIN_MS=40] [RAYS=131072] [STRUCTURES=bvh-sah,lbvh] [SCENES="..."] [VIEWS="..."] [KINDS="..."] \
#       scripts/bench_heldout.sh [OUT.md] [arbor-bench paths options...]
# For every shared model and the builtin scenes `default` and `cornell`, three views fixed in
# advance (view seeds 2027, 4093, 7919: camera and light placed by engine/ray_views.h; the
# benchmark's files use the one framed camera and seed 1) and the ray kinds of KINDS (primary; shadow
# with unnormalized directions and tfar just short of the light, from points facing a point light;
# three more shadow recipes so that no one recipe is tuned to: shadow-area towards a square area
# light half the scene's size, shadow-near towards a point light moved among the geometry (0.6
# bounding radii from the centre: segments of all lengths), shadow-all from every point, those
# facing away through the model (mostly occluded); cosine diffuse bounces; random),
# ray seed 100 + view seed, are written with `arbor rays --view-seed` into $ARBOR_RAYS_DIR (default
# build/rays-heldout; anew every run unless REUSE_RAYS=1); then `arbor-bench paths` times each structure's SIMD paths beside Embree's four calls
# (coherent flag on primary and shadow), 2 threads, median of REPEATS, round-robin, and reports per
# ray kind and structure the distribution over all cells of arbor / Embree's fastest call with the
# errors against the scalar path, brute and Embree. Do not tune on these rays: tune on
# scripts/bench_vs_embree.sh's files, report on these. The table goes to OUT.md (default
# build/results/heldout-DATE.md).
# EMBREE4=PREFIX (an Embree 4 installed by scripts/peers/build_embree4.sh PREFIX) times Embree 4
# instead of Debian's Embree 3: arbor-bench is then built in build/release-embree4 (the release
# preset's settings plus ARBOR_EMBREE_MAJOR=4 and embree_DIR under PREFIX); the rays are the same.
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-build/results/heldout-$(date +%Y-%m-%d).md}
[ $# -gt 0 ] && shift
rays=${RAYS:-131072}
dir=${ARBOR_RAYS_DIR:-build/rays-heldout}
models=${ARBOR_MODELS:-../shared/scenes/models}
views=${VIEWS:-"2027 4093 7919"}
structures=${STRUCTURES:-bvh-sah,lbvh}
kinds=${KINDS:-"primary shadow shadow-area shadow-near shadow-all diffuse random"}
if [ -z "${SCENES:-}" ]; then
  [ -d "$models" ] || { echo "bench_heldout.sh: no models folder $models (set ARBOR_MODELS)" >&2; exit 1; }
  SCENES="$(cd "$models" && ls *.obj | sed 's/\.obj$//' | tr '\n' ' ') builtin:default builtin:cornell"
fi
mkdir -p "$dir" "$(dirname "$out")"

cmake --preset release >/dev/null
cmake --build --preset release -j2 --target arbor arbor-bench >/dev/null
bench=build/release/perf/arbor-bench
peer="Embree 3"
if [ -n "${EMBREE4:-}" ]; then
  config=$(find "$EMBREE4" -name embree-config.cmake 2>/dev/null | head -1)
  [ -n "$config" ] || { echo "bench_heldout.sh: no Embree 4 under EMBREE4=$EMBREE4 (scripts/peers/build_embree4.sh PREFIX)" >&2; exit 1; }
  embree_dir=$(cd "$(dirname "$config")" && pwd)
  cmake -S . -B build/release-embree4 -G Ninja -DCMAKE_BUILD_TYPE=Release -DARBOR_EMBREE_MAJOR=4 \
    -Dembree_DIR="$embree_dir" >/dev/null
  grep -q '^ARBOR_HAVE_EMBREE:INTERNAL=ON' build/release-embree4/CMakeCache.txt ||
    { echo "bench_heldout.sh: build/release-embree4 did not find Embree 4 in $embree_dir" >&2; exit 1; }
  cmake --build build/release-embree4 -j2 --target arbor-bench >/dev/null
  bench=build/release-embree4/perf/arbor-bench
  peer="Embree ${embree_dir##*/embree-}"
fi

arbor=build/release/apps/arbor/arbor
for scene in $SCENES; do
  case $scene in builtin:*) src=$scene ;; *) src="$models/$scene.obj" ;; esac
  stem=${scene//:/-}
  for v in $views; do
    for kind in $kinds; do
      f="$dir/$stem-v$v-$kind.rays"
      case $kind in
        shadow-area) make=(--kind shadow --light-size 0.5) ;;
        shadow-near) make=(--kind shadow --light-distance 0.6) ;;
        shadow-all) make=(--kind shadow --from all) ;;
        *) make=(--kind "$kind") ;;
      esac
      # Written anew every run (~1.5 min for all 144 files): files kept from an older arbor are
      # not the held-out set any more once ray generation changes (as when the samplers moved to
      # one splitmix64). REUSE_RAYS=1 keeps existing files.
      { [ "${REUSE_RAYS:-0}" = 1 ] && [ -f "$f" ]; } || ARBOR_SHARED_SCENES=$(dirname "$models") $arbor rays --scene "$src" "${make[@]}" --count "$rays" \
        --view-seed "$v" --seed $((100 + v)) -o "$f" >/dev/null
    done
  done
done

view_list=$(for v in $views; do printf 'v%s,' "$v"; done); view_list=${view_list%,}
scene_list=$(echo $SCENES | tr ' ' ',')
kind_list=$(echo $kinds | tr ' ' ',')
{
  echo "# arbor vs $peer on held-out rays ($(date +%Y-%m-%d))"
  echo
  echo "- machine: $(lscpu | sed -n 's/^Model name:\s*//p'), $(nproc) hardware threads; $(c++ --version | head -1); git $(git rev-parse --short HEAD 2>/dev/null || echo '?')"
  echo "- rays: $rays per file: \`arbor rays --scene SCENE --kind KIND --count $rays --view-seed V --seed 100+V\` for V in $views (8x8 tile order; shadow-area = --kind shadow --light-size 0.5, shadow-near = --kind shadow --light-distance 0.6, shadow-all = --kind shadow --from all); scenes: $SCENES"
  ARBOR_SHARED_SCENES=$(dirname "$models") $bench paths --rays "$dir" --models "$models" --scenes "$scene_list" \
    --views "$view_list" --kinds "$kind_list" --structures "$structures" --paths single,packet,best --threads 2 \
    --repeats "${REPEATS:-5}" --min-ms "${MIN_MS:-40}" "$@"
} >"$out.tmp"
mv "$out.tmp" "$out"
echo "report: $out"
