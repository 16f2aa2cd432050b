#!/usr/bin/env bash
# The pip package (docs/python.md, "Installing the package"), for ctest: python_package.
#
#   python_package_test.sh PYTHON CHECKOUT BUILD_DIR SHARED_SCENES
#
# PYTHON is the interpreter the module was built for; BUILD_DIR the configured build whose module is
# reused (ARBOR_CMAKE_BUILD_DIR), so nothing is compiled again: the package gets that build's
# binaries, not a portable build from scratch (docs/python.md says what this does not cover).
#  1. a refused ARBOR_CMAKE_BUILD_DIR fails the install with a one-line error naming it;
#  2. venv 1: `pip install --no-build-isolation CHECKOUT`, `import arbor` from outside the trees,
#     then tests/python_package_check.py (files, version, RUNPATH, ldd) and the pytest suite;
#  3. `python3 -m build --wheel --no-isolation`: one linux_x86_64 wheel, installed into venv 2,
#     then the same checks and suite there.
# pip never reaches the network (--no-index); every failure is a FAIL line and exit status 1.
set -euo pipefail
[ $# -eq 4 ] || { echo "usage: $0 PYTHON CHECKOUT BUILD_DIR SHARED_SCENES" >&2; exit 2; }
fail() { echo "FAIL: $*"; exit 1; }
python=$1
src=$(cd "$2" && pwd)
build=$(cd "$3" && pwd)
[ -d "$4/models" ] || fail "no shared models in $4/models"
scenes=$(cd "$4" && pwd)
here=$(cd "$(dirname "$0")" && pwd)

# Everything (the environments, the wheel, the suite's copy) goes in a temporary folder outside the
# source and build trees, removed when the test passes and kept, with its logs, when it fails.
work=$(mktemp -d "${TMPDIR:-/tmp}/arbor-python-package.XXXXXX")
trap 'status=$?; if [ $status -eq 0 ]; then rm -rf "$work"; else echo "(kept: $work)"; fi' EXIT
unset PYTHONPATH PYTHONHOME
export PIP_NO_INDEX=1 PIP_DISABLE_PIP_VERSION_CHECK=1 PIP_NO_CACHE_DIR=1 PIP_NO_INPUT=1
export ARBOR_CMAKE_BUILD_DIR=$build ARBOR_SHARED_SCENES=$scenes

# The suite and the checker run from copies, so no folder of the checkout is on sys.path (a
# script's own folder is); tests read, relative to their own folder, ../../README.md, the source
# stubs in ../arbor (compared with the installed ones) and ../../tests/data/meshes. The source
# package folder is not importable from there: the checker imports the installed arbor first.
mkdir -p "$work/suite/python" "$work/suite/tests/data"
cp -r "$src/python/tests" "$work/suite/python/tests"
cp -r "$src/python/arbor" "$work/suite/python/arbor"
cp -r "$src/tests/data/meshes" "$work/suite/tests/data/meshes"
cp "$src/README.md" "$work/suite/README.md"
cp "$here/python_package_check.py" "$work/check.py"

check() {  # check VENV: imports arbor from a folder outside both trees, then the checks and suite
  local venv=$1
  (cd "$work/suite" && "$venv/bin/python" -c "import arbor; print(arbor.__version__)") \
    || fail "import arbor in $venv"
  (cd "$work/suite" && "$venv/bin/python" "$work/check.py" --source "$src" \
    --tests "$work/suite/python/tests") || fail "the package installed in $venv (above)"
}

echo "== a refused ARBOR_CMAKE_BUILD_DIR"
"$python" -m venv --system-site-packages "$work/venv1"
if (cd "$src" && ARBOR_CMAKE_BUILD_DIR="$work/no-such-build" "$work/venv1/bin/python" -m pip install -q \
      --no-index --no-build-isolation "$src") >"$work/refused.log" 2>&1; then
  fail "pip install succeeded with ARBOR_CMAKE_BUILD_DIR=$work/no-such-build"
fi
grep -q "ARBOR_CMAKE_BUILD_DIR=$work/no-such-build: not a configured CMake build folder" "$work/refused.log" \
  || { cat "$work/refused.log"; fail "no one-line error naming ARBOR_CMAKE_BUILD_DIR (pip's output above)"; }
"$work/venv1/bin/python" -c "import arbor" 2>/dev/null && fail "arbor importable in venv 1 after a failed install"

echo "== venv 1: pip install --no-build-isolation (reusing $build)"
(cd "$src" && "$work/venv1/bin/python" -m pip install -q --no-index --no-build-isolation "$src") \
  || fail "pip install --no-build-isolation $src"
check "$work/venv1"

echo "== the wheel, installed into venv 2"
(cd "$src" && "$python" -m build --wheel --no-isolation --outdir "$work/dist" "$src") >"$work/build.log" 2>&1 \
  || { cat "$work/build.log"; fail "python3 -m build --wheel --no-isolation (output above)"; }
wheels=("$work"/dist/*.whl)
[ ${#wheels[@]} -eq 1 ] || fail "expected one wheel in $work/dist, found: ${wheels[*]}"
name=$(basename "${wheels[0]}")
tag=$("$python" -c "import sys; print(f'cp{sys.version_info[0]}{sys.version_info[1]}')")
[[ $name == arbor-*-$tag-$tag-linux_x86_64.whl ]] || fail "wheel $name: expected arbor-VERSION-$tag-$tag-linux_x86_64.whl"
"$python" -m venv --system-site-packages "$work/venv2"
"$work/venv2/bin/python" -m pip install -q --no-index "${wheels[0]}" || fail "pip install $name"
check "$work/venv2"
echo "python_package: both installs pass"
