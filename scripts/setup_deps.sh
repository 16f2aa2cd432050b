#!/usr/bin/env bash
# Installs the Debian 12 packages arbor needs, only those missing (idempotent).
set -euo pipefail
packages=(
  build-essential cmake ninja-build pkg-config python3
  libxsimd-dev libtbb-dev libglm-dev libopenexr-dev libpng-dev libtinyobjloader-dev
  libcli11-dev nlohmann-json3-dev doctest-dev
  libbenchmark-dev libembree-dev python3-matplotlib python3-numpy
  clang libclang-rt-14-dev
  pybind11-dev python3-dev python3-numpy python3-pytest python3-hypothesis python3-mypy
  python3-venv python3-setuptools python3-wheel python3-build
  libassimp-dev libstb-dev
  libopenmpi-dev openmpi-bin
  libturbojpeg0-dev chromium
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "installing: ${missing[*]}"
  sudo_cmd=""
  [ "$(id -u)" -ne 0 ] && sudo_cmd="sudo"
  $sudo_cmd apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi
