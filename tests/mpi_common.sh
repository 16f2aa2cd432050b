# Sourced by tests/mpi_test.sh and tests/mpi_absent_test.sh after `set -u`: ARBOR (the first
# argument, made absolute), a WORK folder removed on exit, Open MPI allowed to run as root (CI runs
# as root), fail() counting failures in `fails`, and a clear failure when mpirun is missing.
ARBOR=$(realpath "$1")
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
fails=0
fail() { echo "FAIL: $*"; fails=$((fails + 1)); }
command -v mpirun >/dev/null || { echo "FAIL: mpirun not found (scripts/setup_deps.sh installs openmpi-bin)"; exit 1; }
