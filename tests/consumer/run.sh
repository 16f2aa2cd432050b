#!/usr/bin/env bash
# The install-consumer test. Installs the build tree into a scratch prefix and checks that it holds
# only the public header and the libraries libarbor.so and libarbor.a (and the commands arbor and
# arbor-bench, arbor linking no Embree); then builds the README's C++ example (the first ```cpp block
# of its section "Use arbor from C++", copied out of README.md) twice as a separate project with the
# compiler's default flags, once against libarbor.so (arbor::arbor) and once against libarbor.a
# (arbor::arbor_static), checks that libarbor.a defines every function libarbor.so exports, that no flag of arbor's own reached its compile line, that the
# static program needs no libarbor.so, and runs both on a model. The build's own compiler is used when given (a sanitizer build's library needs
# that compiler's runtime).
# Usage: run.sh BUILD_DIR WORK_DIR README.md MODEL.obj [CXX]
set -eu
build=$1; work=$2; readme=$3; model=$4; cxx=${5:-}
[ -f "$model" ] || { echo "FAIL: model $model not found (../shared/scenes is needed)"; exit 1; }
rm -rf "$work"; mkdir -p "$work/src"
awk '/^## Use arbor from C\+\+/ {s = 1} s == 1 && /^```cpp/ {s = 2; next} s == 2 && /^```/ {exit} s == 2 {print}' \
  "$readme" > "$work/src/main.cpp"
grep -q 'arbor/arbor.h' "$work/src/main.cpp" || { echo "FAIL: no C++ example found in $readme"; exit 1; }
cp "$(dirname "$0")/CMakeLists.txt" "$work/src/"
# The product first (component Unspecified: what a package without the lab tool holds), then the
# lab tool's component "bench" where this build made arbor-bench (the test command's sanitizer
# phase builds only what its tests run, and arbor-bench is not among them).
cmake --install "$build" --prefix "$work/prefix" --component Unspecified >/dev/null
if [ -e "$work/prefix/bin/arbor-bench" ]; then echo "FAIL: component Unspecified installed arbor-bench"; exit 1; fi
if [ -e "$build/perf/arbor-bench" ]; then
  cmake --install "$build" --prefix "$work/prefix" --component bench >/dev/null
  [ -x "$work/prefix/bin/arbor-bench" ] || { echo "FAIL: component bench did not install arbor-bench"; exit 1; }
fi
headers=$(cd "$work/prefix/include" && find . -type f | sort)
if [ "$headers" != "./arbor/arbor.h" ]; then
  echo "FAIL: the installed tree holds more than <arbor/arbor.h>:"; echo "$headers"; exit 1
fi
archives=$(cd "$work/prefix" && find . -name '*.a' | sed 's|.*/||' | sort)
if [ "$archives" != "libarbor.a" ]; then
  echo "FAIL: the installed tree should hold exactly one static library, libarbor.a; it holds: ${archives:-none}"; exit 1
fi
# libarbor.a defines every function libarbor.so exports (a source file missing from the static
# library's list leaves its members undefined for static programs only).
so=$(find "$work/prefix" -name libarbor.so | head -1); a=$(find "$work/prefix" -name libarbor.a | head -1)
missing=$(comm -23 <(nm -D --defined-only "$so" | awk '$2 ~ /[TW]/ {print $3}' | sort -u) \
                   <(nm --defined-only "$a" 2>/dev/null | awk '$2 ~ /[TW]/ {print $3}' | sort -u))
if [ -n "$missing" ]; then echo "FAIL: libarbor.a lacks what libarbor.so exports:"; echo "$missing" | c++filt | head; exit 1; fi
# The installed product links no Embree (only the lab tool arbor-bench, installed beside it, may).
if ldd "$work/prefix/bin/arbor" | grep -qi embree; then echo "FAIL: the installed arbor links Embree"; exit 1; fi
for link in shared static; do
  out="$work/build-$link"
  cmake -S "$work/src" -B "$out" -DARBOR_LINK=$link -DCMAKE_PREFIX_PATH="$work/prefix" \
    -DCMAKE_EXPORT_COMPILE_COMMANDS=ON ${cxx:+-DCMAKE_CXX_COMPILER="$cxx"} >/dev/null
  cmake --build "$out" >/dev/null
  line=$(grep '"command"' "$out/compile_commands.json")
  for flag in -march -ffp-contract -std= -fno-math-errno -O; do
    if grep -q -- "$flag" <<<"$line"; then echo "FAIL ($link): the package put $flag on the consumer's compile line: $line"; exit 1; fi
  done
  needs=$(ldd "$out/consumer" | grep -c 'libarbor\.so' || true)
  if [ "$link" = static ] && [ "$needs" != 0 ]; then echo "FAIL: the static consumer still needs libarbor.so"; exit 1; fi
  if [ "$link" = shared ] && [ "$needs" = 0 ]; then echo "FAIL: the shared consumer does not link libarbor.so"; exit 1; fi
  echo "== $link"
  "$out/consumer" "$model"
done
