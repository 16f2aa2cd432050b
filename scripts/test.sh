#!/usr/bin/env bash
# The whole test suite: install what is missing, build and test the release preset, then build and
# test the sanitizer preset (ASan + UBSan).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup-deps.sh
jobs=$(nproc)
start=$(date +%s)
cmake --preset release >/dev/null
cmake --build --preset release -j "$jobs"
ctest --preset release -j "$jobs"
cmake --preset sanitize >/dev/null
cmake --build --preset sanitize -j "$jobs"
ctest --preset sanitize -j "$jobs"
echo "all tests passed in $(( $(date +%s) - start )) s"
