#!/usr/bin/env bash
# The benchmark report in one command (docs/benchmarks.md, "The benchmark matrix"):
#   scripts/bench.sh           full matrix, about 15 minutes on the 2-core reference machine
#   scripts/bench.sh --quick   small scenes, about 2 minutes
# Builds the release preset, runs `arbor-bench bench`, draws the plots, writes the summary tables
# (scripts/bench_summary.py) and describes the machine, all into build/results/DATE/ (DATE-quick/
# for --quick; ARBOR_BENCH_OUT=DIR overrides). Further arguments go to `arbor-bench bench`.
set -euo pipefail
cd "$(dirname "$0")/.."
suffix=""
for a in "$@"; do [ "$a" = "--quick" ] && suffix="-quick"; done
out=${ARBOR_BENCH_OUT:-build/results/$(date +%Y-%m-%d)$suffix}
mkdir -p "$out"

cmake --preset release >/dev/null
cmake --build --preset release -j2 --target arbor-bench arbor >/dev/null

{
  echo "# Machine"
  echo
  echo '```'
  lscpu | grep -E '^(Architecture|Model name|CPU\(s\)|Thread|Core|Socket|L1d|L2|L3|Hypervisor|Flags)' |
    sed -E 's/^(Flags:\s+).*/\1(avx2: '"$(grep -qw avx2 /proc/cpuinfo && echo yes || echo no)"', avx512f: '"$(grep -qw avx512f /proc/cpuinfo && echo yes || echo no)"')/'
  echo "Memory:        $(free -g | awk '/^Mem:/ {print $2 " GiB"}')"
  echo "Kernel:        $(uname -r)"
  echo "Compiler:      $(c++ --version | head -1)"
  echo "CMake:         $(cmake --version | head -1)"
  for p in libtbb-dev libxsimd-dev libembree-dev libglm-dev; do
    echo "$p: $(dpkg-query -W -f='${Version}' "$p" 2>/dev/null || echo 'not installed')"
  done
  echo "git:           $(git rev-parse --short HEAD 2>/dev/null || echo '?')"
  echo "load average:  $(cut -d' ' -f1-3 /proc/loadavg) (before the run; other processes share the cores)"
  echo '```'
} >"$out/machine.md"

build/release/perf/arbor-bench bench -o "$out" "$@"
/usr/bin/python3 scripts/plot_bench.py "$out/bench.json" "$out"
/usr/bin/python3 scripts/bench_summary.py "$out/bench.json" >"$out/tables.md"
echo "Whole script (build, matrix, plots): ${SECONDS} s; load average after: $(cut -d' ' -f1-3 /proc/loadavg)" >>"$out/machine.md"
echo "report: $out/bench.md, tables $out/tables.md (machine: $out/machine.md), ${SECONDS} s"
