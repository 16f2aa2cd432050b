#!/usr/bin/env bash
# Installs the build tree into a scratch prefix, then configures, builds and runs the consumer
# (with the build's own compiler, when given: the sanitizer flags the package exports are the
# compiler's own, e.g. clang's -fsanitize=fuzzer-no-link in the preset fuzz).
set -eu
build=$1; work=$2; cxx=${3:-}
rm -rf "$work"; mkdir -p "$work"
cmake --install "$build" --prefix "$work/prefix" >/dev/null
cmake -S "$(dirname "$0")" -B "$work/build" -DCMAKE_PREFIX_PATH="$work/prefix" -DCMAKE_BUILD_TYPE=Release \
  ${cxx:+-DCMAKE_CXX_COMPILER="$cxx"} >/dev/null
cmake --build "$work/build" >/dev/null
"$work/build/consumer"
