#!/usr/bin/env bash
# Interleaved A/B (A B, B A, ...), 1 thread, CPU time: $BIN/bench_A (BIN default /tmp/h68-ab) = bench_paths of main 245e589,
# bench_B = of the branch (release preset), copied there first. Each run: scripts/bench_vs_embree.sh's
# files (bunny, beast, rocker arm, seed 1) in BENCH, then the tuning views v11, v12 (alligator, woody,
# beast, bunny; `arbor rays --view-seed S --seed 20+S`) in TUNE.
#   ab.sh OUTDIR ROUNDS BENCH TUNE; B / A: python3 perf/results/2026-12-03e-minima/summarize.py OUTDIR
set -eu
out=$1; rounds=$2; bench=$3; tune=$4
mkdir -p $out
common=(--kinds primary,shadow,diffuse,random --structures bvh-sah,lbvh --paths single,packet,best --threads 1
        --repeats 3 --min-ms 30 --cpu-time --no-embree --brute-sample 64 --models /work/shared/scenes/models)
for ((k = 0; k < rounds; ++k)); do
  if (( k % 2 == 0 )); then order="A B"; else order="B A"; fi
  for s in $order; do
    echo "round $k $s $(date -u +%H:%M:%S) load $(cut -d' ' -f1-3 /proc/loadavg)" >> $out/log
    { ${BIN:-/tmp/h68-ab}/bench_$s --rays $bench --scenes stanford-bunny,beast,rocker-arm "${common[@]}"
      ${BIN:-/tmp/h68-ab}/bench_$s --rays $tune --scenes alligator,woody,beast,stanford-bunny --views v11,v12 "${common[@]}"; } \
      > $out/$s-$k.md 2>&1
  done
done
echo done >> $out/log
