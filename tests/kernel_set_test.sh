#!/usr/bin/env bash
# The portable build with one kernel set forced (ARBOR_ISA=SET): the doctest files whose cases
# compare the SIMD paths with the scalar path and brute (wide BVHs and kd-tree: single and packet
# paths, ties, layouts, leaf floors, the other queries) run on that set, and the set in use must be
# SET (test_kernel_set.cpp). A set this CPU lacks is skipped (exit 77: ctest reports it as skipped).
# With "sanitized" (the ASan phase of scripts/test.sh, where every case runs ~4x slower): the set the
# CPU picks by itself is skipped too (every doctest case of the phase already ran on it), and the
# all-hits and closest-point files are left out (37 of the ~57 CPU seconds per set under ASan).
# Usage: kernel_set_test.sh ARBOR_TESTS SET [sanitized]
set -u
TESTS=$1 SET=$2 MODE=${3:-}
need() {
  for flag in "$@"; do
    grep -qw "$flag" /proc/cpuinfo || { echo "SKIP: this CPU lacks $flag, which the $SET kernel set needs"; exit 77; }
  done
}
case $SET in
  sse4) need sse4_2 ssse3 popcnt ;;
  avx2) need avx2 fma bmi1 bmi2 ;;
  avx512) need avx512f avx512bw avx512dq avx512vl avx512cd ;;
  *) echo "FAIL: unknown set $SET"; exit 1 ;;
esac
has() { for flag in "$@"; do grep -qw "$flag" /proc/cpuinfo || return 1; done; }
files="*test_kernel_set.cpp,*test_wide_paths.cpp,*test_kdtree_simd.cpp,*test_ties.cpp,*test_layouts.cpp,*test_leaf_floor.cpp"
if [ "$MODE" = sanitized ]; then
  widest=sse4
  has avx2 fma bmi1 bmi2 && widest=avx2
  has avx2 fma bmi1 bmi2 avx512f avx512bw avx512dq avx512vl avx512cd && widest=avx512
  [ "$SET" != "$widest" ] || { echo "SKIP: $SET is the set this CPU runs by default: every case of this build ran on it"; exit 77; }
else
  files+=",*test_all_hits.cpp,*test_closest_point.cpp"
fi
ARBOR_ISA=$SET exec "$TESTS" --source-file="$files" --no-version
