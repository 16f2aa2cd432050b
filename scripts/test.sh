#!/usr/bin/env bash
# The whole test suite (CI runs exactly this), in three builds; each phase's seconds are printed at
# the end, also when a phase fails.
#  1. release (gcc -O3): everything is built; the test suite, the CLI, bench and install tests.
#  2. fuzz (clang 14, ASan + UBSan, libFuzzer coverage; a portable build, -DARBOR_PORTABLE=ON): the
#     same tests under ASan + UBSan, but for those of the lab's arbor-bench, which it does not build (the SIMD agreement files once more with each other kernel set
#     the CPU runs forced, tests/kernel_set_test.sh), then the
#     four libFuzzer harnesses (OBJ loader, mesh loader of every format, ray/hit readers, the
#     viewer's message parser) in ARBOR_FUZZ_SECONDS (default 60) on two cores (scripts/fuzz.sh: how
#     they share it, seeds, and where a finding is saved).
#  3. tsan (gcc, ThreadSanitizer, with oneTBB built instrumented by scripts/tsan_tbb.sh): the tests
#     of the parallel builders, of tracing in parallel and of the renderer (tests/CMakeLists.txt
#     picks them).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup_deps.sh
jobs=$(nproc)
fuzz_seconds=${ARBOR_FUZZ_SECONDS:-60}

start=$(date +%s)
times=()
current=""
phase() {  # phase NAME COMMAND...: runs the command and keeps its time
  current=$1; shift
  local t0; t0=$(date +%s)
  echo "== $current"
  "$@"
  times+=("$(printf '%-28s %5d s' "$current" $(( $(date +%s) - t0 )))")
  current=""
}
report() {
  local status=$?
  echo "== phase times"
  [ ${#times[@]} -gt 0 ] && printf '%s\n' "${times[@]}"
  if [ $status -ne 0 ]; then
    echo "FAILED in phase '${current:-?}' after $(( $(date +%s) - start )) s"
  else
    echo "all tests passed in $(( $(date +%s) - start )) s"
  fi
}
trap report EXIT

phase "release: build" bash -c "cmake --preset release >/dev/null && cmake --build --preset release -j $jobs"
phase "release: tests" ctest --preset release -j "$jobs"

phase "asan+ubsan+fuzz: build" bash -c "cmake --preset fuzz >/dev/null && cmake --build --preset fuzz -j $jobs \
  --target arbor_tests arbor_instance_tests arbor arbor_fuzz_obj arbor_fuzz_mesh arbor_fuzz_rays arbor_fuzz_view"
phase "asan+ubsan: tests" ctest --preset fuzz -j "$jobs"
phase "fuzz: ${fuzz_seconds} s on 2 cores" scripts/fuzz.sh "$fuzz_seconds"

phase "tsan: instrumented oneTBB" scripts/tsan_tbb.sh
phase "tsan: build" bash -c "cmake --preset tsan >/dev/null && cmake --build --preset tsan -j $jobs --target arbor_tests"
phase "tsan: tests" ctest --preset tsan -j "$jobs" --no-tests=error
