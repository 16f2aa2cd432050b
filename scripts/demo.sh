#!/usr/bin/env bash
# The main job: install what is missing, build the release preset, render the embedded default
# scene to arbor.exr + arbor.png and print the summary line.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup-deps.sh
cmake --preset release >/dev/null
cmake --build --preset release
build/release/apps/arbor/arbor render -o arbor.exr "$@"
