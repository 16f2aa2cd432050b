#!/usr/bin/env bash
set -eu
out=$1; rounds=$2
mkdir -p $out
R=/work/main/build/rays-heldout
for ((k = 0; k < rounds; ++k)); do
  if (( k % 2 == 0 )); then order="A B"; else order="B A"; fi
  for s in $order; do
    echo "round $k $s $(date -u +%H:%M:%S) load $(cut -d' ' -f1-3 /proc/loadavg)" >> $out/log
    { /tmp/h62-ab/bench_$s --rays $R --scenes stanford-bunny --views v2027 --kinds random,diffuse --structures bvh-sah --paths single --threads 1 --repeats 5 --min-ms 60 --cpu-time --no-embree --brute-sample 0;
      /tmp/h62-ab/bench_$s --rays $R --scenes beast --views v4093 --kinds shadow --structures bvh-sah --paths packet,best --threads 1 --repeats 5 --min-ms 60 --cpu-time --no-embree --brute-sample 0; } > $out/$s-$k.md 2>&1
  done
done
