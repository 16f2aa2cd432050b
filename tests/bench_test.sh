#!/usr/bin/env bash
# The benchmark matrix end to end on the tiny scene: valid JSON/CSV/Markdown whose rows agree with
# each other, every row validated against brute, and one-line errors for bad options. The arguments
# are the command that runs the matrix, e.g. `arbor-bench bench` or `arbor bench`.
set -u
BENCH=("$@")
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
fails=0
fail() { echo "FAIL: $*"; fails=$((fails + 1)); }

if "${BENCH[@]}" --quick --scenes tiny --rays 1024 --repeats 2 --time-brute -q -o "$WORK/out" >"$WORK/stdout" 2>"$WORK/stderr"; then
  python3 - "$WORK/out" <<'PY' || fail "bench reports inconsistent"
import csv, json, sys
d = sys.argv[1]
j = json.load(open(d + "/bench.json"))
rows = j["rows"]
assert rows, "no rows"
for k in ["date", "command", "compiler", "libraries", "embree", "hardware_threads", "seconds", "budgets"]:
    assert k in j["meta"], k
kinds = {r["kind"] for r in rows}
assert kinds == {"primary", "shadow", "diffuse", "random"}, kinds
for r in rows:
    assert r["rays"] == 1024 and r["err_brute"] == 0 and r["brute_sample"] > 0, r
    m = r["mrays_per_s"]
    assert m["min"] <= m["median"] <= m["max"], m
    assert len(r["total_ms"]) == len(j["meta"]["budgets"])
assert any(r["structure"] == "brute" for r in rows)
with open(d + "/bench.csv") as f:
    table = list(csv.DictReader(f))
assert len(table) == len(rows), (len(table), len(rows))
assert table[0]["scene"] == "tiny" and float(table[0]["mrays_per_s"]) > 0
md = open(d + "/bench.md").read()
assert "## Headline" in md and "## Trace matrix" in md
PY
else
  fail "${BENCH[*]} --quick exited $?: $(tail -3 "$WORK/stderr")"
fi

expect_error() {
  local needle=$1; shift
  "$@" >"$WORK/o" 2>"$WORK/e"
  local rc=$?
  if [ $rc -lt 1 ] || [ $rc -gt 127 ]; then fail "$* -> exit $rc"; return; fi
  [ "$(wc -l <"$WORK/e")" -eq 1 ] || fail "$* -> stderr: $(cat "$WORK/e")"
  grep -qF -- "$needle" "$WORK/e" || fail "$* -> stderr lacks '$needle': $(cat "$WORK/e")"
}
expect_error "--scenes" "${BENCH[@]}" --scenes nowhere -q -o "$WORK/x"
expect_error "--structures" "${BENCH[@]}" --scenes tiny --structures octree -q -o "$WORK/x"
expect_error "--kinds" "${BENCH[@]}" --scenes tiny --kinds ambient -q -o "$WORK/x"
expect_error "--rays" "${BENCH[@]}" --rays 0 -o "$WORK/x"

[ $fails -eq 0 ] && echo "bench tests passed"
# Not `exit $fails`: exit statuses are taken mod 256, so 256 failures would exit 0.
[ $fails -eq 0 ] || { echo "$fails failure(s)"; exit 1; }
