#!/bin/bash
# Interleaved A/B of two bench_paths binaries (A B, B A, A B, ...), bvh-sah, 1 thread, CPU time, no Embree:
#   ABIN=old/bench_paths BBIN=new/bench_paths ab.sh OUTDIR ROUNDS KINDS PATHS SCENES RAYDIR [VIEWS]
# then: python3 summarize.py OUTDIR  (per cell the median over rounds of B/A, then per kind and path
# the median, min and max over the cells; and the errors against the scalar path, all rays).
out=$1; rounds=$2; kinds=$3; paths=$4; scenes=$5; rays=$6; views=${7:-}
mkdir -p $out
models=${ARBOR_MODELS:-$(cd "$(dirname "$0")/../../.." && pwd)/../shared/scenes/models}
export ARBOR_SHARED_SCENES=$(dirname "$models")
vopt=""; [ -n "$views" ] && vopt="--views $views"
for r in $(seq 1 $rounds); do
  if [ $((r % 2)) = 1 ]; then order="A B"; else order="B A"; fi
  for w in $order; do
    if [ $w = A ]; then bin=$ABIN; else bin=$BBIN; fi
    echo "$w round $r start $(date +%T) load $(cut -d' ' -f1 /proc/loadavg)" >> $out/log
    $bin --rays $rays --models $models --scenes $scenes $vopt --kinds $kinds --structures bvh-sah \
      --paths $paths --threads ${THREADS:-1} --repeats ${REPEATS:-3} --min-ms ${MINMS:-30} --cpu-time --no-embree --brute-sample ${BRUTE:-0} > $out/$w-$r.log 2>&1
  done
done
echo done >> $out/log
