#!/usr/bin/env bash
# Process-level A/B (perf/results/heldout-minima-2026-12-03e.md): /tmp/h62-ab/bench_A = bench_paths of
# main f840fbf, /tmp/h62-ab/bench_B = bench_paths of the branch (both the release preset), copied there
# first. Rounds alternate A B, B A, ...; summarize.py OUTDIR gives B / A per cell and round.
# A B B A x ROUNDS/2 ... : ab.sh OUTDIR ROUNDS PATHS  (held-out files, 1 thread, CPU time)
set -eu
out=$1; rounds=$2; paths=$3
mkdir -p $out
R=/work/main/build/rays-heldout
for ((k = 0; k < rounds; ++k)); do
  if (( k % 2 == 0 )); then order="A B"; else order="B A"; fi
  for s in $order; do
    echo "round $k $s $(date -u +%H:%M:%S) load $(cut -d' ' -f1-3 /proc/loadavg)" >> $out/log
    /tmp/h62-ab/bench_$s --rays $R --scenes builtin:default,alligator,stanford-bunny,teapot,builtin:cornell --views v2027 \
      --kinds primary,shadow,diffuse,random --structures bvh-sah,lbvh --paths $paths --threads 1 --repeats 3 --min-ms 30 \
      --cpu-time --no-embree --brute-sample 64 > $out/$s-$k.md 2>&1
  done
done
