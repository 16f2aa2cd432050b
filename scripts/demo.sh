#!/usr/bin/env bash
# The main job: install what is missing, build `arbor` (only it and what it links: the tests, the
# benchmarks and the Python module are scripts/test.sh's), render the embedded default scene to
# arbor.exr + arbor.png and print the summary line.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup_deps.sh
cmake --preset release >/dev/null
cmake --build --preset release --target arbor
build/release/apps/arbor/arbor render -o arbor.exr "$@"
