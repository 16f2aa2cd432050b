#!/usr/bin/env bash
# A build without MPI (ARBOR_MPI=OFF: the sanitizer presets): `arbor render` works as ever, and
# under mpirun it stops with one clear line saying it was built without MPI, an exit status of
# 1..127 and no output, rather than every rank rendering the whole frame alone. Needs Open MPI's
# mpirun (scripts/setup_deps.sh installs it): fails, not skips, without it.
set -u
. "$(dirname "$0")/mpi_common.sh"
small=(--width 40 --height 24 --spp 1 -q)

"$ARBOR" render "${small[@]}" -o "$WORK/plain.exr" >"$WORK/out" 2>&1 && [ -s "$WORK/plain.exr" ] \
  || fail "plain render in a build without MPI: $(cat "$WORK/out")"

timeout 120 mpirun --oversubscribe -np 2 "$ARBOR" render "${small[@]}" -o "$WORK/mpi.exr" >"$WORK/out" 2>"$WORK/err"
rc=$?
{ [ $rc -ge 1 ] && [ $rc -le 127 ]; } || fail "mpirun -np 2 arbor (built without MPI) exited $rc: $(cat "$WORK/err")"
grep -q "^arbor: MPI: this arbor was built without MPI" "$WORK/err" || fail "no clear line: $(cat "$WORK/err")"
[ -z "$(ls "$WORK" | grep '^mpi')" ] || fail "an output was written: $(ls "$WORK")"

[ $fails -eq 0 ] && echo "mpi_absent tests passed"
# Not `exit $fails`: exit statuses are taken mod 256, so 256 failures would exit 0.
[ $fails -eq 0 ] || { echo "$fails failure(s)"; exit 1; }
