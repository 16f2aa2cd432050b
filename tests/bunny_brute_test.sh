#!/usr/bin/env bash
# `arbor trace --accel brute --json` on the Stanford bunny with rays from `arbor rays` agrees with an
# independent double-precision ray/triangle test written here in numpy (Moller-Trumbore over every
# triangle), by the spec/rayfile.md rule; the JSON has the fields spec/cli.md names. Rays whose
# nearest hit lies within 1e-6 (barycentric) of an edge of a triangle, or whose two nearest hits
# are closer than the tolerance, may be decided either way by the two tests and are not counted.
set -u
ARBOR=$1
SHARED=$2
PY=/usr/bin/python3
BUNNY="$SHARED/models/stanford-bunny.obj"
if [ ! -f "$BUNNY" ]; then echo "FAIL: no $BUNNY (this test needs ../shared)"; exit 1; fi
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
for kind in primary random; do
  "$ARBOR" rays --scene "$BUNNY" --kind $kind --count 512 -o "$WORK/$kind.rays" --seed 3 >/dev/null || exit 1
  "$ARBOR" trace --scene "$BUNNY" --rays "$WORK/$kind.rays" --hits "$WORK/$kind.hits" --accel brute --json >"$WORK/$kind.json" || exit 1
  "$PY" - "$BUNNY" "$WORK/$kind.rays" "$WORK/$kind.hits" "$WORK/$kind.json" $kind <<'PY' || exit 1
import json, struct, sys
import numpy as np

obj, rays_path, hits_path, json_path, kind = sys.argv[1:6]
j = json.load(open(json_path))
for k in ["accel", "triangles", "rays", "hits", "build_ms", "trace_ms", "mrays_per_s", "threads",
          "nodes", "leaves", "max_depth", "sah_cost", "bytes_per_triangle"]:
    assert k in j, f"JSON lacks {k}"
V, F = [], []
for line in open(obj):
    p = line.split()
    if not p: continue
    if p[0] == "v": V.append([float(x) for x in p[1:4]])
    elif p[0] == "f":
        idx = [int(t.split("/")[0]) for t in p[1:]]
        idx = [i - 1 if i > 0 else len(V) + i for i in idx]
        for k in range(1, len(idx) - 1): F.append([idx[0], idx[k], idx[k + 1]])  # fan, as rayfile.md numbers them
V = np.array(V, dtype=np.float32).astype(np.float64)
F = np.array(F)
assert j["accel"] == "brute" and j["triangles"] == len(F), (j["triangles"], len(F))
A, B, C = V[F[:, 0]], V[F[:, 1]], V[F[:, 2]]
E1, E2 = B - A, C - A
data = open(rays_path, "rb").read()
n = struct.unpack("<IQ", data[4:16])[1]
R = np.frombuffer(data, dtype="<f4", offset=16, count=8 * n).reshape(n, 8).astype(np.float64)
hd = open(hits_path, "rb").read()
assert hd[:4] == b"HITS" and struct.unpack("<IQ", hd[4:16])[1] == n
H = np.frombuffer(hd, dtype=np.dtype([("t", "<f4"), ("prim", "<u4"), ("u", "<f4"), ("v", "<f4")]), offset=16, count=n)
assert j["rays"] == n and j["hits"] == int(np.sum(H["prim"] != 0xFFFFFFFF)), (j["rays"], j["hits"])
checked = skipped = bad = 0
for i in range(n):
    o, tn, d, tf = R[i, 0:3], R[i, 3], R[i, 4:7], R[i, 7]
    P = np.cross(d, E2)
    det = np.einsum("ij,ij->i", E1, P)
    with np.errstate(divide="ignore", invalid="ignore"):
        inv = 1.0 / det
        T = o - A
        u = np.einsum("ij,ij->i", T, P) * inv
        Q = np.cross(T, E1)
        v = (Q @ d) * inv
        t = np.einsum("ij,ij->i", E2, Q) * inv
    ok = (det != 0) & (u >= 0) & (v >= 0) & (u + v <= 1) & (t >= tn) & (t <= tf)
    near = (det != 0) & (u > -1e-6) & (v > -1e-6) & (u + v < 1 + 1e-6) & (t >= tn) & (t <= tf)
    edge = near & ~((u > 1e-6) & (v > 1e-6) & (u + v < 1 - 1e-6))
    ts = np.sort(t[ok])
    got_hit = H["prim"][i] != 0xFFFFFFFF
    if edge.any() and (not ok.any() or t[edge].min() <= ts[0] * (1 + 1e-4) + 1e-4):
        skipped += 1  # the nearest candidate is on an edge: either answer is right
        continue
    if len(ts) > 1 and ts[1] - ts[0] <= 1e-4 * max(1.0, abs(ts[0])):
        skipped += 1
        continue
    checked += 1
    if not ok.any():
        bad += got_hit
    elif not got_hit or abs(H["t"][i] - ts[0]) > 1e-4 * max(1.0, abs(ts[0])):
        bad += 1
print(f"{kind}: {checked} rays ({int(np.sum(H['prim'] != 0xFFFFFFFF))} hits) checked against the float64 test, {skipped} edge/tie rays left out, {bad} disagree")
assert bad == 0 and checked >= 0.9 * n, (bad, checked)
PY
done
echo "brute on the bunny agrees with the float64 test"
