#!/usr/bin/env bash
# Fine-grained A/B: short runs (one scene set each, ~5 s) alternating A B, B A, ... so that the machine's drift
# (other helpers' builds) moves both alike. ab2.sh OUTDIR ROUNDS RAYS SCENES VIEWS KINDS STRUCTURES PATHS
# /tmp/h63-ab/bench_A = bench_paths of main 1bb614e, bench_B = of h63 d3b033e (release preset), copied there first.
# B / A per cell and round: python3 perf/results/2026-12-03e-minima/summarize.py OUTDIR
set -eu
out=$1; rounds=$2; rays=$3; scenes=$4; views=$5; kinds=$6; structures=$7; paths=$8
mkdir -p $out
vopt=(); [ "$views" != - ] && vopt=(--views "$views")
for ((k = 0; k < rounds; ++k)); do
  if (( k % 2 == 0 )); then order="A B"; else order="B A"; fi
  for s in $order; do
    echo "round $k $s $(date -u +%H:%M:%S) load $(cut -d' ' -f1-3 /proc/loadavg)" >> $out/log
    ARBOR_SHARED_SCENES=/work/shared /tmp/h63-ab/bench_$s --rays $rays --models /work/shared/scenes/models \
      --scenes $scenes "${vopt[@]}" --kinds $kinds --structures $structures --paths $paths --threads 1 --repeats 3 \
      --min-ms 30 --cpu-time --no-embree --brute-sample 64 > $out/$s-$k.md 2>&1
  done
done
echo done >> $out/log
