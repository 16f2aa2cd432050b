#!/usr/bin/env bash
# `arbor bench` without the harness in `arbor`: arbor links no Embree, `arbor --help` lists bench,
# `arbor bench ARGS` runs arbor-bench's matrix (help, a tiny run, its option errors), and
# arbor-bench lists its sub-commands and refuses an unknown one in one line with exit 2.
set -u
ARBOR=$1
ARBOR_BENCH=$2
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
fails=0
fail() { echo "FAIL: $*"; fails=$((fails + 1)); }

# The product binary links neither Embree nor the benchmark harness.
if ldd "$ARBOR" >"$WORK/ldd" 2>&1; then
  grep -qi embree "$WORK/ldd" && fail "arbor links Embree: $(grep -i embree "$WORK/ldd")"
else
  fail "ldd $ARBOR failed: $(cat "$WORK/ldd")"
fi
nm -C "$ARBOR" 2>/dev/null | grep -q "arbor::perf::" && fail "arbor holds arbor::perf symbols (the benchmark harness)"

"$ARBOR" --help >"$WORK/help" 2>&1 || fail "arbor --help exited $?"
grep -qE "^ *bench +.*arbor-bench" "$WORK/help" || fail "arbor --help does not list bench: $(cat "$WORK/help")"

"$ARBOR" bench --help >"$WORK/bhelp" 2>&1 || fail "arbor bench --help exited $?"
grep -q -- "--scenes" "$WORK/bhelp" || fail "arbor bench --help lacks --scenes: $(head -5 "$WORK/bhelp")"

if "$ARBOR" bench --quick --scenes tiny --kinds primary --structures bvh-sah --rays 256 --repeats 1 -q \
    -o "$WORK/out" >"$WORK/stdout" 2>"$WORK/stderr"; then
  grep -q "^arbor bench: .* rows in " "$WORK/stdout" || fail "arbor bench summary line: $(cat "$WORK/stdout")"
  python3 - "$WORK/out/bench.json" <<'PY' || fail "arbor bench report"
import json, sys
j = json.load(open(sys.argv[1]))
assert j["rows"], "no rows"
assert j["meta"]["command"].startswith("arbor bench "), j["meta"]["command"]
PY
else
  fail "arbor bench exited $?: $(tail -3 "$WORK/stderr")"
fi
"$ARBOR" bench --rays 0 -o "$WORK/x" >/dev/null 2>"$WORK/e"
rc=$?
[ $rc -eq 2 ] || fail "arbor bench --rays 0 -> exit $rc"
[ "$(wc -l <"$WORK/e")" -eq 1 ] && grep -q "^arbor: --rays" "$WORK/e" || fail "arbor bench --rays 0 -> stderr: $(cat "$WORK/e")"

"$ARBOR_BENCH" --help >"$WORK/abhelp" 2>&1 || fail "arbor-bench --help exited $?"
for sub in bench paths bvh lbvh kdtree load build-once trace-once kernels; do
  grep -qE "^  $sub +[a-zA-Z]" "$WORK/abhelp" || fail "arbor-bench --help does not list $sub"
done
"$ARBOR_BENCH" nosuch >/dev/null 2>"$WORK/e"
rc=$?
[ $rc -eq 2 ] || fail "arbor-bench nosuch -> exit $rc"
[ "$(wc -l <"$WORK/e")" -eq 1 ] && grep -q "^arbor-bench: unknown sub-command 'nosuch' (expected one of bench, " "$WORK/e" ||
  fail "arbor-bench nosuch -> stderr: $(cat "$WORK/e")"

[ $fails -eq 0 ] && echo "bench forward tests passed"
[ $fails -eq 0 ] || { echo "$fails failure(s)"; exit 1; }
