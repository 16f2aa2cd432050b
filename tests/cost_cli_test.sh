#!/usr/bin/env bash
# `arbor render --integrator cost` (spec/cli.md): an EXR with the layers nodes and tris (several
# structures side by side), a PNG sheet of the documented size with a line per structure on
# stdout, `-o X.png` for the picture alone; option errors exit 2 with one line naming the option.
set -u
ARBOR=$1
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
fails=0
fail() { echo "FAIL: $*"; fails=$((fails + 1)); }

# expect_usage NEEDLE CMD...: exit 2, one stderr line containing NEEDLE
expect_usage() {
  local needle=$1; shift
  "$@" >"$WORK/out" 2>"$WORK/err"
  local rc=$?
  [ $rc -eq 2 ] || { fail "$* -> exit $rc (expected 2): $(cat "$WORK/err")"; return; }
  [ "$(wc -l <"$WORK/err")" -eq 1 ] || { fail "$* -> stderr: $(cat "$WORK/err")"; return; }
  grep -qF -- "$needle" "$WORK/err" || fail "$* -> stderr lacks '$needle': $(cat "$WORK/err")"
}

printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 4 3\n' >"$WORK/quad.obj"
if "$ARBOR" render "$WORK/quad.obj" --integrator cost --accel brute,bvh-sah,kdtree --width 64 --height 48 --spp 1 \
    -q -o "$WORK/cost.exr" >"$WORK/out" 2>"$WORK/err"; then
  grep -q "^plan: cost, 1 spp, structure brute,bvh-sah,kdtree" "$WORK/out" || fail "no plan line: $(cat "$WORK/out")"
  for a in brute bvh-sah kdtree; do
    grep -q "^$a: built in .* per camera ray: .* nodes visited" "$WORK/out" || fail "no cost line for $a: $(cat "$WORK/out")"
    grep -q "^$a: camera rays at .* Mrays/s (median of 5" "$WORK/out" || fail "no speed line for $a: $(cat "$WORK/out")"
  done
  /usr/bin/python3 - "$WORK/cost.exr" "$WORK/cost.png" <<'PY' || fail "cost outputs wrong"
import struct, sys
def exr_header(path):
    d = open(path, "rb").read()
    assert d[:4] == b"\x76\x2f\x31\x01", "not an EXR"
    p, attrs = 8, {}
    while d[p] != 0:
        name_end = d.index(b"\0", p); name = d[p:name_end].decode()
        type_end = d.index(b"\0", name_end + 1); size = struct.unpack("<i", d[type_end + 1:type_end + 5])[0]
        attrs[name] = d[type_end + 5:type_end + 5 + size]; p = type_end + 5 + size
    chans, q, raw = [], 0, attrs["channels"]
    while raw[q] != 0:
        e = raw.index(b"\0", q); chans.append(raw[q:e].decode()); q = e + 1 + 16
    x0, y0, x1, y1 = struct.unpack("<4i", attrs["dataWindow"])
    return chans, x1 - x0 + 1, y1 - y0 + 1
chans, w, h = exr_header(sys.argv[1])
assert sorted(chans) == ["nodes", "tris"], chans
assert (w, h) == (3 * 64, 48), (w, h)
png = open(sys.argv[2], "rb").read()
assert png[:8] == b"\x89PNG\r\n\x1a\n"
pw, ph = struct.unpack(">II", png[16:24])
# engine/cost_sheet.h: 3 panels of 64 x 48 at text scale 1: 3*64 + 4*4 wide, 4 + 2*(3*9 + 48 + 4 + 8 + 2 + 9 + 4) high
assert (pw, ph) == (208, 208), (pw, ph)
PY
else
  fail "render --integrator cost exited $?: $(cat "$WORK/err")"
fi
# -o X.png: the picture alone.
"$ARBOR" render "$WORK/quad.obj" --integrator cost --accel lbvh --width 16 --height 12 --spp 1 -q -o "$WORK/only.png" \
  >"$WORK/out" 2>&1 || fail "render --integrator cost -o only.png exited $?: $(cat "$WORK/out")"
[ -s "$WORK/only.png" ] || fail "no only.png"
[ -e "$WORK/only.exr" ] && fail "-o only.png also wrote an EXR"

expect_usage "--accel" "$ARBOR" render "$WORK/quad.obj" --accel brute,bvh-sah -o "$WORK/x.exr"
expect_usage "nope" "$ARBOR" render "$WORK/quad.obj" --integrator cost --accel brute,nope -o "$WORK/x.exr"
expect_usage "--layers" "$ARBOR" render "$WORK/quad.obj" --integrator cost --layers z -o "$WORK/x.exr"
expect_usage "-o" "$ARBOR" render "$WORK/quad.obj" --integrator cost -o "$WORK/x.pfm"
expect_usage "--integrator" "$ARBOR" converge "$WORK/quad.obj" --out "$WORK/c" --integrator cost
[ -e "$WORK/x.exr" ] || [ -e "$WORK/x.pfm" ] && fail "a refused command wrote x.exr or x.pfm"

[ $fails -eq 0 ] && echo "cost cli tests passed"
[ $fails -eq 0 ]
