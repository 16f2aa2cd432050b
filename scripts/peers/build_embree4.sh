#!/usr/bin/env bash
# Builds Embree 4 from source for the benchmark's Embree 4 peer (docs/benchmarks.md, "Against Embree 4"):
#   [EMBREE_SRC=CHECKOUT] [JOBS=2] scripts/peers/build_embree4.sh [PREFIX]
# Debian 12 packages only Embree 3, and Embree is never vendored into this repository: the script takes
# the checkout in EMBREE_SRC, else clones the pinned release tag below into build/embree4-src, builds it in
# build/embree4-build and installs it into PREFIX (default build/embree4; build/ is ignored by git).
# Only what arbor-bench uses is built, to keep the build short: triangles and single-level instances
# (perf/embree_peer.cpp), ray packets (rtcIntersect8/16), TBB tasking (Debian's libtbb-dev), Release,
# kernels for AVX2 and AVX-512 only (Embree picks the best one the CPU has at run time). The library
# then needs an AVX2 CPU: Embree 4.4.1 cannot leave out its AVX kernels while keeping SSE2 ones (its
# BVH8 code is then compiled into the AVX kernels only, and libembree4 does not link), and SSE2, SSE4.2
# and AVX kernels would never run on the lab's AVX-512 machines, so only their build time is saved. Curves, grids, points, quads,
# subdivision surfaces, user geometry, instance arrays, tutorials, tests and ISPC are off; ray masks and
# filter functions keep Embree's defaults (on), as in Debian's Embree 3, so both peers run the same
# traversal kernels' features. Prints the embree_DIR to hand to arbor's configure.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
tag=v4.4.1
prefix=$(realpath -m "${1:-$root/build/embree4}")
work="$root/build"
jobs=${JOBS:-2}

src=${EMBREE_SRC:-}
if [ -z "$src" ]; then
  src="$work/embree4-src"
  [ -d "$src/.git" ] || git clone --depth 1 --branch "$tag" https://github.com/RenderKit/embree "$src"
fi
src=$(realpath "$src")
version=$(sed -n 's/^SET(EMBREE_VERSION_\(MAJOR\|MINOR\|PATCH\) \([0-9]*\))/\2/p' "$src/CMakeLists.txt" | paste -sd.)
case "$version" in
4.*) ;;
*) echo "build_embree4: $src is Embree '$version', not 4.x" >&2; exit 1 ;;
esac

build="$work/embree4-build"
generator=()
command -v ninja >/dev/null && generator=(-G Ninja)
nice -n 10 cmake -S "$src" -B "$build" "${generator[@]}" \
  -DCMAKE_BUILD_TYPE=Release -DCMAKE_INSTALL_PREFIX="$prefix" \
  -DEMBREE_TASKING_SYSTEM=TBB -DEMBREE_MAX_ISA=NONE \
  -DEMBREE_ISA_SSE2=OFF -DEMBREE_ISA_SSE42=OFF -DEMBREE_ISA_AVX=OFF -DEMBREE_ISA_AVX2=ON -DEMBREE_ISA_AVX512=ON \
  -DEMBREE_GEOMETRY_TRIANGLE=ON -DEMBREE_GEOMETRY_INSTANCE=ON -DEMBREE_GEOMETRY_INSTANCE_ARRAY=OFF \
  -DEMBREE_GEOMETRY_QUAD=OFF -DEMBREE_GEOMETRY_CURVE=OFF -DEMBREE_GEOMETRY_SUBDIVISION=OFF \
  -DEMBREE_GEOMETRY_USER=OFF -DEMBREE_GEOMETRY_GRID=OFF -DEMBREE_GEOMETRY_POINT=OFF \
  -DEMBREE_RAY_PACKETS=ON -DEMBREE_TUTORIALS=OFF -DEMBREE_ISPC_SUPPORT=OFF -DBUILD_TESTING=OFF \
  -DEMBREE_ZIP_MODE=OFF -DEMBREE_INSTALL_DEPENDENCIES=OFF -DEMBREE_STATIC_LIB=OFF
start=$(date +%s)
nice -n 10 cmake --build "$build" -j"$jobs"
nice -n 10 cmake --install "$build" >/dev/null
echo "Embree $version ($(basename "$src"), tag $tag unless EMBREE_SRC says otherwise) built in $(($(date +%s) - start)) s"
dir=$(dirname "$(find "$prefix" -name embree-config.cmake | head -1)")
echo "embree_DIR=$dir"
