#!/usr/bin/env bash
# Fuzzes the OBJ loader, the mesh loader of every format (PLY; STL and glTF through Assimp), the ray-file
# readers and the viewer's message parser (libFuzzer, preset fuzz: clang + ASan + UBSan) in SECONDS
# (default 60) on two cores: the OBJ loader then the mesh loader for half of it each on one core, the
# ray readers for 2/3 of it then the message parser for the rest on the other (the parser is small:
# its coverage stops growing within seconds). Seeds: tests/fuzz/seeds, the committed regressions, the
# loader test files (tests/data/meshes), ../shared/scenes/bad, the first vertices and faces of
# ../shared/scenes/models, and small
# PLY/STL/glTF files good and broken (tests/fuzz/seeds/mesh, written by scripts/fuzz_seeds.py mesh).
# A finding (crash, sanitizer report, FuzzFinding) is saved under build/fuzz/findings/ and fails the
# run: commit the input under tests/fuzz/regressions/{obj,mesh,rays,view}/ (the doctest suite replays
# them all), then fix the bug.
set -euo pipefail
cd "$(dirname "$0")/.."
export LSAN_OPTIONS="suppressions=$(pwd)/tests/lsan.supp${LSAN_OPTIONS:+:$LSAN_OPTIONS}"  # third-party leaks only (tests/lsan.supp)
seconds=${1:-60}
shared=${ARBOR_SHARED_SCENES:-../shared/scenes}
build=build/fuzz
cmake --preset fuzz >/dev/null
cmake --build --preset fuzz -j "$(nproc)"

work=$build/work
rm -rf "$work" "$build/findings"
mkdir -p "$work"/{seeds,corpus}-{obj,mesh,rays,view} "$build/findings"
cp tests/fuzz/seeds/obj/* "$work/seeds-obj/"
cp tests/fuzz/seeds/obj/* tests/fuzz/seeds/mesh/* "$work/seeds-mesh/"
cp tests/fuzz/regressions/obj/* "$work/seeds-obj/" 2>/dev/null || true
cp tests/fuzz/regressions/mesh/* "$work/seeds-mesh/" 2>/dev/null || true
cp tests/data/meshes/* "$work/seeds-mesh/"
cp tests/fuzz/regressions/rays/* "$work/seeds-rays/" 2>/dev/null || true
cp tests/fuzz/seeds/view/* "$work/seeds-view/"
cp tests/fuzz/regressions/view/* "$work/seeds-view/" 2>/dev/null || true
if [ -d "$shared/bad" ]; then cp "$shared"/bad/*.obj "$work/seeds-obj/"; fi
if [ -d "$shared/models" ]; then python3 scripts/fuzz_seeds.py obj "$work/seeds-obj" "$shared/models"; fi
python3 scripts/fuzz_seeds.py rays "$work/seeds-rays"

obj_seconds=$(( seconds / 2 ))
mesh_seconds=$(( seconds - obj_seconds ))
rays_seconds=$(( seconds * 2 / 3 ))
view_seconds=$(( seconds - rays_seconds ))
run() {
  local name=$1 max_len=$2 time=$3; shift 3
  "$build/fuzz/arbor_fuzz_$name" -max_total_time="$time" -max_len="$max_len" -timeout=10 -rss_limit_mb=2048 \
    -print_final_stats=1 -artifact_prefix="$build/findings/$name-" "$@" "$work/corpus-$name" "$work/seeds-$name" \
    >"$work/$name.log" 2>&1
}
status=0
(run obj 8192 "$obj_seconds" -dict=tests/fuzz/obj.dict && run mesh 8192 "$mesh_seconds" -dict=tests/fuzz/mesh.dict) & obj_pid=$!
(run rays 2064 "$rays_seconds" && run view 4200 "$view_seconds" -dict=tests/fuzz/view.dict) & rays_pid=$!
wait $obj_pid || status=1
wait $rays_pid || status=1
for name in obj mesh rays view; do
  t=$seconds; [ $name = obj ] && t=$obj_seconds; [ $name = mesh ] && t=$mesh_seconds
  [ $name = rays ] && t=$rays_seconds; [ $name = view ] && t=$view_seconds
  [ -f "$work/$name.log" ] || { echo "fuzz $name: not run (the harness before it failed)"; continue; }
  execs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$work/$name.log" | grep -o '[0-9]*$' || echo '?')
  cov=$(grep -o 'cov: [0-9]*' "$work/$name.log" | tail -1 || echo 'cov: ?')
  echo "fuzz $name: $execs runs in ${t}s, $cov, corpus $(ls "$work/corpus-$name" | wc -l) new inputs"
done
if [ $status -ne 0 ]; then
  echo "fuzzing found a problem (logs: $work/obj.log, $work/mesh.log, $work/rays.log, $work/view.log)"
  for name in obj mesh rays view; do [ -f "$work/$name.log" ] && grep -E "ERROR|FuzzFinding|what\(\)|SUMMARY" "$work/$name.log" | head -5 || true; done
  for f in "$build"/findings/*; do
    [ -e "$f" ] || continue
    name=$(basename "$f"); name=${name%%-*}
    echo "reproducer: $f   (replay: $build/fuzz/arbor_fuzz_$name $f)"
  done
fi
exit $status
