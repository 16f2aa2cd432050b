#!/usr/bin/env bash
# A/B after /work/main/perf/results/2026-12-03e-minima/ab.sh: A = main 1bb614e's bench_paths, B = h64's;
# rounds A B, B A, ...; 1 thread, CPU time. Two sets per run: the benchmark files (bench_vs_embree.sh's
# seed-1 files, 4 kinds) and h64's shadow tuning set (view seeds 11-22, 3 weakest per model).
set -eu
out=$1; rounds=$2
mkdir -p $out/bench $out/tune
for ((k = 0; k < rounds; ++k)); do
  if (( k % 2 == 0 )); then order="A B"; else order="B A"; fi
  for s in $order; do
    echo "round $k $s $(date -u +%H:%M:%S) load $(cut -d' ' -f1-3 /proc/loadavg)" >> $out/log
    /tmp/h64-ab/bench_$s --rays /tmp/h64-bench --models /work/shared/scenes/models --scenes stanford-bunny,beast,rocker-arm \
      --kinds primary,shadow,diffuse,random --structures bvh-sah,lbvh,kdtree --paths packet,best --threads 1 --repeats 3 --min-ms 30 \
      --cpu-time --no-embree --brute-sample 64 > $out/bench/$s-$k.md 2>&1
    /tmp/h64-ab/bench_$s --rays /tmp/h64-tune --models /work/shared/scenes/models --scenes beast,rocker-arm,stanford-bunny,teapot --views w1,w2,w3 \
      --kinds shadow --structures bvh-sah,lbvh,kdtree --paths packet,best --threads 1 --repeats 3 --min-ms 30 \
      --cpu-time --no-embree --brute-sample 64 > $out/tune/$s-$k.md 2>&1
  done
done
