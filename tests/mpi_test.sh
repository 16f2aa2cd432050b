#!/usr/bin/env bash
# `mpirun -np N arbor render|converge` (spec/cli.md, "Across machines"): the image of N = 1, 2, 3
# ranks equals the single-process image bit for bit (default scene and Cornell box, path traced;
# converge, direct, on 2 and 3 ranks);
# rank 0 alone prints and writes; a plain call loads no MPI; a rank that crashes, throws, runs out
# of memory, is killed or stops answering mid-frame, mpirun interrupted, or a rank's guardian
# killed, stops the job within its bound with one line naming the rank and cause, a set exit status
# and no output written or overwritten; a rank with another scene file or other settings is refused.
# Every mpirun runs under `timeout`. Needs Open MPI's mpirun (the MPI front end is built).
set -u
. "$(dirname "$0")/mpi_common.sh"
# A shared CI machine has 2 cores: 3 ranks need --oversubscribe.
MPIRUN=(timeout 120 mpirun --oversubscribe)

small=(--width 70 --height 45 --spp 2 --integrator path -q)   # 5 x 3 tiles of 16; converge takes the size only
cornell=(builtin:cornell --integrator path --width 64 --height 48 --spp 4 -q)

# 1. Bit-identical images for N = 1, 2, 3 ranks.
for scene in default cornell; do
  if [ $scene = default ]; then args=("${small[@]}"); else args=("${cornell[@]}"); fi
  "$ARBOR" render "${args[@]}" -o "$WORK/$scene-single.exr" --threads 2 >"$WORK/single.out" 2>&1 \
    || fail "$scene: single-process render failed: $(cat "$WORK/single.out")"
  for n in 1 2 3; do
    out="$WORK/$scene-$n.exr"
    if "${MPIRUN[@]}" -np $n "$ARBOR" render "${args[@]}" -o "$out" --threads 1 >"$WORK/mpi.out" 2>"$WORK/mpi.err"; then
      cmp -s "$WORK/$scene-single.exr" "$out" || fail "$scene: the image of $n ranks differs from the single-process one"
      cmp -s "$WORK/$scene-single.png" "$WORK/$scene-$n.png" || fail "$scene: the PNG of $n ranks differs"
      grep -q "rendered in .* on $n ranks\? -> " "$WORK/mpi.out" || fail "$scene: no 'on $n ranks' summary: $(cat "$WORK/mpi.out")"
      [ "$(grep -c '^plan:' "$WORK/mpi.out")" -eq 1 ] || fail "$scene: $n ranks printed more than rank 0's lines: $(cat "$WORK/mpi.out")"
    else
      fail "$scene: mpirun -np $n exited $?: $(cat "$WORK/mpi.err")"
    fi
  done
done
# The parts of the frame really came from several ranks: rank 0 kept from rendering, the image
# is still the same (rank 1 rendered all of it and sent every tile).
if ARBOR_MPI_ROOT_RENDERS=0 "${MPIRUN[@]}" -x ARBOR_MPI_ROOT_RENDERS -np 2 "$ARBOR" render "${small[@]}" \
     -o "$WORK/idle.exr" >"$WORK/mpi.out" 2>"$WORK/mpi.err"; then
  cmp -s "$WORK/default-single.exr" "$WORK/idle.exr" || fail "tiles rendered on rank 1 only: image differs"
else
  fail "ARBOR_MPI_ROOT_RENDERS=0 mpirun -np 2 exited $?: $(cat "$WORK/mpi.err")"
fi

# 2. converge: the same CSV (but for the times) and reference on 2 and 3 ranks as in one process.
"$ARBOR" converge "${small[@]:0:4}" --out "$WORK/cv1" --max-spp 4 --no-plot >/dev/null 2>&1 || fail "converge failed"
for n in 2 3; do
  if "${MPIRUN[@]}" -np $n "$ARBOR" converge "${small[@]:0:4}" --out "$WORK/cv$n" --max-spp 4 --no-plot \
       >"$WORK/mpi.out" 2>"$WORK/mpi.err"; then
    [ "$(cut -d, -f1-3,5-8 "$WORK/cv1/converge.csv")" = "$(cut -d, -f1-3,5-8 "$WORK/cv$n/converge.csv")" ] \
      || fail "converge on $n ranks: CSV differs: $(cat "$WORK/cv$n/converge.csv")"
    cmp -s "$WORK/cv1/reference-direct.exr" "$WORK/cv$n/reference-direct.exr" || fail "converge on $n ranks: references differ"
    grep -q "converge.csv on $n ranks" "$WORK/mpi.out" || fail "converge: no 'on $n ranks': $(cat "$WORK/mpi.out")"
  else
    fail "converge: mpirun -np $n exited $?: $(cat "$WORK/mpi.err")"
  fi
done

# 3. bench: the report of 2 ranks holds every row of the 1-rank report: the same keys, in plan
# order, with the same accuracy and structure columns (errors against brute, Embree and the scalar
# path, rays validated, tree statistics); only timings may differ.
# --bind-to none: Open MPI binds each of 2 ranks to one core, which would change "all threads".
bench=(bench --quick --scenes tiny,replicated-1e3 --kinds primary,shadow --rays 256 --build-repeats 1 --repeats 1 -q)
"$ARBOR" "${bench[@]}" -o "$WORK/b1" >/dev/null 2>"$WORK/err" || fail "arbor bench failed: $(cat "$WORK/err")"
for rpn in 2 1; do
  if "${MPIRUN[@]}" --bind-to none -np 2 "$ARBOR" "${bench[@]}" -o "$WORK/b2-$rpn" --ranks-per-node $rpn \
       >"$WORK/mpi.out" 2>"$WORK/mpi.err"; then
    grep -q "rows in .* on 2 ranks -> " "$WORK/mpi.out" || fail "bench: no 'on 2 ranks': $(cat "$WORK/mpi.out")"
    python3 - "$WORK/b1/bench.json" "$WORK/b2-$rpn/bench.json" $rpn <<'PY' || fail "bench on 2 ranks, --ranks-per-node $rpn"
import json, sys
one, two, rpn = json.load(open(sys.argv[1])), json.load(open(sys.argv[2])), int(sys.argv[3])
key = lambda r: (r["scene"], r["kind"], r["threads"], r["structure"], r["path"])
a, b = [key(r) for r in one["rows"]], [key(r) for r in two["rows"]]
assert a and sorted(a) == sorted(b), (set(a) ^ set(b))
assert [key(r) for r in two["rows"]] == a, "rows out of plan order"
same = ("err_brute", "err_embree", "err_scalar", "validated_rays", "brute_sample", "rays", "query", "triangles",
        "nodes", "leaves", "max_depth", "sah_cost", "nodes_per_ray", "tris_per_ray", "bytes_per_triangle")
assert sum(r["validated_rays"] or 0 for r in one["rows"]) > 0, "no row validated"
for r1, r2 in zip(one["rows"], two["rows"]):
    assert set(r1) <= set(r2), (key(r1), set(r1) - set(r2))
    assert "err_brute" in r1, key(r1)
    for c in same:
        assert r1.get(c) == r2.get(c), (key(r1), c, r1.get(c), r2.get(c))
akey = lambda x: (x["scene"], x["kind"], x["threads"], x["budget"])
assert sorted(map(akey, one["auto"])) == sorted(map(akey, two["auto"]))
ranks = {r["rank"] for r in two["rows"]}
# Both ranks share one machine: with --ranks-per-node 1 only rank 0 times rows.
assert ranks == ({0, 1} if rpn == 2 else {0}), ranks
PY
  else
    fail "bench: mpirun -np 2 --ranks-per-node $rpn exited $?: $(cat "$WORK/mpi.err")"
  fi
done

# 4. A plain call neither loads nor initialises MPI; the launcher's variables are what tell.
LD_DEBUG=files "$ARBOR" render "${small[@]}" -o "$WORK/plain.exr" >/dev/null 2>"$WORK/ld.err" || fail "plain render failed"
grep -q "libmpi" "$WORK/ld.err" && fail "a plain call loaded libmpi"
grep -q "arbor_mpi.so" "$WORK/ld.err" && fail "a plain call loaded arbor_mpi.so"
# Under mpirun without the module: a clear line naming where it looked, exit 1..127, no output.
ARBOR_MPI_MODULE=$WORK/none.so "${MPIRUN[@]}" -x ARBOR_MPI_MODULE -np 1 "$ARBOR" render "${small[@]}" \
  -o "$WORK/x.exr" >/dev/null 2>"$WORK/err"
rc=$?
{ [ $rc -ge 1 ] && [ $rc -le 127 ] && grep -q "^arbor: MPI: the module arbor_mpi.so is missing (looked for $WORK/none.so" "$WORK/err" \
  && [ ! -e "$WORK/x.exr" ]; } || fail "mpirun without the module: exit $rc $(cat "$WORK/err")"
# --mpi joins without a launcher (Open MPI's singleton start): a job of 1 rank.
timeout 120 "$ARBOR" render --mpi "${small[@]}" -o "$WORK/single-mpi.exr" >"$WORK/out" 2>"$WORK/err" \
  && grep -q "on 1 rank -> " "$WORK/out" && cmp -s "$WORK/default-single.exr" "$WORK/single-mpi.exr" \
  || fail "--mpi without mpirun: $(cat "$WORK/out" "$WORK/err")"
LD_DEBUG=files "${MPIRUN[@]}" -x LD_DEBUG -np 1 "$ARBOR" render "${small[@]}" -o "$WORK/y.exr" 2>&1 | grep -q "libmpi" \
  || fail "under mpirun libmpi was not loaded"

# 5. Faults: one line naming the rank (from rank 0, or from the guardian of a rank killed by a
# signal), exit 1..127, no output written or overwritten.
# expect_stop EXIT NEEDLE ENV... -- ARGS...: runs 2 ranks on the Cornell box, writing kept.exr: an
# existing one must survive; with fresh=1, there is none before and none may appear. With
# within=S the job must end within S seconds of its start, with after=S not before S seconds.
fresh=0 within=0 after=0
expect_stop() {
  local want_rc=$1 needle=$2; shift 2
  local envs=() xs=()
  while [ "$1" != "--" ]; do envs+=("$1"); xs+=(-x "${1%%=*}"); shift; done
  shift
  rm -f "$WORK"/kept.*
  [ $fresh = 1 ] || echo "keep me" >"$WORK/kept.exr"
  local t0; t0=$(date +%s%N)
  env "${envs[@]}" "${MPIRUN[@]}" "${xs[@]}" -np 2 "$@" >"$WORK/out" 2>"$WORK/err"
  local rc=$?
  local ms=$(( ($(date +%s%N) - t0) / 1000000 ))
  echo "[$needle] exit $rc after $ms ms"
  [ "$within" = 0 ] || [ $ms -le $((within * 1000)) ] || fail "[$needle] took $ms ms, bound $within s: $(cat "$WORK/err")"
  [ "$after" = 0 ] || [ $ms -ge $((after * 1000)) ] || fail "[$needle] ended after $ms ms, before $after s: $(cat "$WORK/err")"
  case $want_rc in
    1..127) { [ $rc -ge 1 ] && [ $rc -le 127 ]; } || fail "[$needle] exit $rc, want 1..127: $(cat "$WORK/err")";;
    *) [ $rc -eq "$want_rc" ] || fail "[$needle] exit $rc, want $want_rc: $(cat "$WORK/err")";;
  esac
  [ "$(grep -c '^arbor: ' "$WORK/err")" -eq 1 ] || fail "[$needle] not one 'arbor:' line: $(cat "$WORK/err")"
  grep -q -- "$needle" "$WORK/err" || fail "[$needle] missing from: $(cat "$WORK/err")"
  if [ $fresh = 1 ]; then
    [ -z "$(ls "$WORK" | grep kept)" ] || fail "[$needle] an output was written: $(ls "$WORK")"
  else
    [ "$(tr -d '\0' <"$WORK/kept.exr")" = "keep me" ] || fail "[$needle] the existing output was overwritten"
  fi
  [ ! -e "$WORK/kept.png" ] || fail "[$needle] a PNG was written"
  ls "$WORK" | grep -q "kept.exr." && fail "[$needle] a temporary output was left behind"
  rm -f "$WORK/kept.png"
}
frame=("$ARBOR" render "${cornell[@]}" --threads 1 -o "$WORK/kept.exr")
# Rank 0 only hands out tiles here, so that rank 1 surely renders the 12 tiles of the frame and
# fails at the tile asked however loaded the machine is; rank 0 surely renders its first tile.
idle=ARBOR_MPI_ROOT_RENDERS=0
expect_stop 4 "arbor: rank 1: crashed: SIGSEGV" $idle ARBOR_MPI_TEST_FAULT=1:2:segv -- "${frame[@]}"
expect_stop 4 "arbor: rank 1: test fault after 3 tiles" $idle ARBOR_MPI_TEST_FAULT=1:3:throw -- "${frame[@]}"
expect_stop 3 "arbor: rank 1: out of memory" $idle ARBOR_MPI_TEST_FAULT=1:1:oom -- "${frame[@]}"
expect_stop 4 "arbor: rank 0: crashed: SIGABRT" ARBOR_MPI_TEST_FAULT=0:1:abort -- "${frame[@]}"
# A rank killed mid-frame: SIGKILL cannot be caught, so the rank's guardian (the process mpirun
# started) names it and exits 4 (mpirun alone would exit 128 + 9); a SIGTERM from a user, to the
# rank or to its guardian, is a fault reported by rank 0 with its sender.
fresh=1 expect_stop 4 "arbor: rank 1 (pid [0-9]* on .*) was killed by SIGKILL" $idle ARBOR_MPI_TEST_FAULT=1:3:kill \
  -- "${frame[@]}"
expect_stop 4 "arbor: rank 1: stopped by SIGTERM (sent by pid [0-9]*)" $idle ARBOR_MPI_TEST_FAULT=1:3:term \
  -- "${frame[@]}"
expect_stop 4 "arbor: rank 1: stopped by SIGTERM (sent by pid [0-9]*)" $idle ARBOR_MPI_TEST_FAULT=1:2:term-guardian \
  -- "${frame[@]}"
expect_stop 4 "arbor: rank 0 (pid [0-9]* on .*) was killed by SIGKILL" ARBOR_MPI_TEST_FAULT=0:1:kill -- "${frame[@]}"
# A rank that stops answering (SIGSTOP mid-frame) is found by the heartbeat: its watcher names it
# once the deadline (5 s) has passed, and the job ends (mpirun resumes and stops the rank). Bound:
# start-up and the first tiles (about 1 s), the deadline, mpirun's teardown (about 1 s), plus 5 s
# of margin for a loaded machine.
fresh=1 within=12 after=5 expect_stop 4 \
  "arbor: rank 1 (pid [0-9]* on .*) has not answered for [5-9] s (stopped, hung, or cut off from rank 0); the job stops" \
  $idle ARBOR_MPI_TEST_FAULT=1:2:stop -- "${frame[@]}"
fresh=1 within=12 after=5 expect_stop 4 \
  "arbor: rank 0 (pid [0-9]* on .*) has not answered for [5-9] s (stopped, hung, or cut off from rank 1); the job stops" \
  ARBOR_MPI_TEST_FAULT=0:1:stop -- "${frame[@]}"
# Ctrl-C to mpirun (a SIGINT to mpirun alone: the ranks run in process groups of their own, so a
# terminal's Ctrl-C reaches mpirun only). mpirun stops the ranks (SIGTERM after 1 s) and exits 1
# whatever they do; rank 0 says why. Bound: start-up, mpirun's 1 s, margin.
fresh=1 within=8 expect_stop 1 \
  "arbor: interrupted: mpirun stopped the job (Ctrl-C, or SIGINT, SIGTERM or SIGHUP sent to mpirun) while all 2 ranks ran; rank 0 wrote nothing" \
  $idle ARBOR_MPI_TEST_FAULT=1:2:interrupt -- "${frame[@]}"
# The guardian killed (SIGKILL): its rank reports it to rank 0, which names it. mpirun's status is
# 137 here, its own rule for the process it started dying by a signal (128 + 9), which no process
# of the job can change (docs/mpi.md).
fresh=1 within=8 expect_stop 137 \
  "arbor: rank 1: its guardian (pid [0-9]* on .*, the process mpirun started) was killed (SIGKILL" \
  $idle ARBOR_MPI_TEST_FAULT=1:2:kill-guardian -- "${frame[@]}"
# A job that runs several times longer than a (shortened) deadline, every rank busy rendering, is
# not stopped.
if ARBOR_MPI_HEARTBEAT=0.5 "${MPIRUN[@]}" -x ARBOR_MPI_HEARTBEAT -np 2 "$ARBOR" render builtin:cornell --integrator path \
     --width 64 --height 48 --spp 256 -q --threads 1 -o "$WORK/long.exr" >"$WORK/out" 2>"$WORK/err"; then
  [ -s "$WORK/long.exr" ] || fail "heartbeat 0.5 s: no image"
else
  fail "heartbeat 0.5 s: a healthy job was stopped: $(cat "$WORK/err")"
fi

# Ranks that disagree: another file with the same name in another folder, another setting, a
# file missing on one rank.
mkdir -p "$WORK/a" "$WORK/b"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' >"$WORK/a/s.obj"
printf 'v 0 0 0\nv 1 0 0\nv 0 1.5 0\nf 1 2 3\n' >"$WORK/b/s.obj"
two_ranks() {  # two_ranks WDIR0 WDIR1 ARGS0 -- ARGS1: MPMD, one rank each
  local w0=$1 w1=$2 a0=() a1=(); shift 2
  while [ "$1" != "--" ]; do a0+=("$1"); shift; done
  shift; a1=("$@")
  echo "keep me" >"$WORK/kept.exr"
  "${MPIRUN[@]}" -np 1 --wdir "$w0" "$ARBOR" render "${a0[@]}" : -np 1 --wdir "$w1" "$ARBOR" render "${a1[@]}" \
    >"$WORK/out" 2>"$WORK/err"
  echo $?
}
q=(--width 32 --height 32 -q -o "$WORK/kept.exr")
rc=$(two_ranks "$WORK/a" "$WORK/b" s.obj "${q[@]}" -- s.obj "${q[@]}")
{ [ "$rc" -eq 1 ] && grep -q "arbor: rank 1 (pid .*): its scene is not rank 0's" "$WORK/err" \
  && [ "$(cat "$WORK/kept.exr")" = "keep me" ]; } || fail "another scene file on rank 1: exit $rc $(cat "$WORK/err")"
rc=$(two_ranks "$WORK/a" "$WORK/a" s.obj "${q[@]}" -- s.obj "${q[@]}" --spp 3)
{ [ "$rc" -eq 1 ] && grep -q "its settings are not rank 0's" "$WORK/err"; } \
  || fail "other settings on rank 1: exit $rc $(cat "$WORK/err")"
rc=$(two_ranks "$WORK/a" "$WORK" s.obj "${q[@]}" -- s.obj "${q[@]}")
{ [ "$rc" -eq 1 ] && grep -q "arbor: rank 1: s.obj: cannot open" "$WORK/err" \
  && [ "$(grep -c '^arbor: ' "$WORK/err")" -eq 1 ]; } || fail "a file missing on rank 1: exit $rc $(cat "$WORK/err")"

[ $fails -eq 0 ] && echo "mpi tests passed"
# Not `exit $fails`: exit statuses are taken mod 256, so 256 failures would exit 0.
[ $fails -eq 0 ] || { echo "$fails failure(s)"; exit 1; }
