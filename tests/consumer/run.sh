#!/usr/bin/env bash
# Installs the build tree into a scratch prefix, checks that it holds only the public header and
# library, then configures, builds and runs the consumer (the README's example) with the compiler's
# default flags, and checks that no flag of arbor's own reached its compile line. The build's own
# compiler is used when given (a sanitizer build's library needs that compiler's runtime).
# Usage: run.sh BUILD_DIR WORK_DIR MODEL.obj [CXX]
set -eu
build=$1; work=$2; model=$3; cxx=${4:-}
[ -f "$model" ] || { echo "FAIL: model $model not found (../shared/scenes is needed)"; exit 1; }
rm -rf "$work"; mkdir -p "$work"
cmake --install "$build" --prefix "$work/prefix" >/dev/null
headers=$(cd "$work/prefix/include" && find . -type f | sort)
if [ "$headers" != "./arbor/arbor.h" ]; then
  echo "FAIL: the installed tree holds more than <arbor/arbor.h>:"; echo "$headers"; exit 1
fi
if find "$work/prefix" -name '*.a' | grep -q .; then echo "FAIL: static libraries installed"; exit 1; fi
cmake -S "$(dirname "$0")" -B "$work/build" -DCMAKE_PREFIX_PATH="$work/prefix" -DCMAKE_EXPORT_COMPILE_COMMANDS=ON \
  ${cxx:+-DCMAKE_CXX_COMPILER="$cxx"} >/dev/null
cmake --build "$work/build" >/dev/null
line=$(grep '"command"' "$work/build/compile_commands.json")
for flag in -march -ffp-contract -std= -fno-math-errno -O; do
  if grep -q -- "$flag" <<<"$line"; then echo "FAIL: the package put $flag on the consumer's compile line: $line"; exit 1; fi
done
"$work/build/consumer" "$model"
