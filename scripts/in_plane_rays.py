#!/usr/bin/env python3
"""Rays lying in the plane of a flat model, as .rays files (spec/rayfile.md) for `arbor trace` and
`arbor-bench paths`: origins at uniform random points of the model's triangles, directions in the
model's plane at uniform random angles. Only for models flat along one axis (woody and alligator of
the shared models lie in z = 0); refuses others by name.

    scripts/in_plane_rays.py OUT_DIR MODELS_DIR [NAME ...] [--count N] [--seed S]

writes OUT_DIR/<name>-inplane.rays (default names: woody alligator; N = 262144)."""
import argparse
import math
import os
import random
import struct
import sys


def load_obj(path):
    verts, tris = [], []
    with open(path, errors="replace") as f:
        for line in f:
            w = line.split()
            if not w:
                continue
            if w[0] == "v":
                verts.append(tuple(float(x) for x in w[1:4]))
            elif w[0] == "f":
                idx = [int(t.split("/")[0]) for t in w[1:]]
                idx = [i - 1 if i > 0 else len(verts) + i for i in idx]
                for j in range(1, len(idx) - 1):
                    tris.append((idx[0], idx[j], idx[j + 1]))
    return verts, tris


def f32(x):
    return struct.unpack("<f", struct.pack("<f", x))[0]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("out_dir")
    ap.add_argument("models_dir")
    ap.add_argument("names", nargs="*", default=["woody", "alligator"])
    ap.add_argument("--count", type=int, default=262144)
    ap.add_argument("--seed", type=int, default=5)
    a = ap.parse_args()
    os.makedirs(a.out_dir, exist_ok=True)
    for name in a.names:
        path = os.path.join(a.models_dir, name + ".obj")
        verts, tris = load_obj(path)
        flat = [k for k in range(3) if len({f32(v[k]) for v in verts}) == 1]
        if not flat:
            sys.exit(f"in_plane_rays.py: {path}: the model is not flat along any axis")
        k = flat[0]
        plane = f32(verts[0][k])
        u_axis, v_axis = [j for j in range(3) if j != k]
        rng = random.Random(a.seed)
        out = bytearray(b"RAYS" + struct.pack("<IQ", 1, a.count))
        for _ in range(a.count):
            t = tris[rng.randrange(len(tris))]
            r1, r2 = rng.random(), rng.random()
            if r1 + r2 > 1.0:
                r1, r2 = 1.0 - r1, 1.0 - r2
            p = [verts[t[0]][j] * (1 - r1 - r2) + verts[t[1]][j] * r1 + verts[t[2]][j] * r2 for j in range(3)]
            p[k] = plane  # exactly in the plane
            ang = rng.random() * 2.0 * math.pi
            d = [0.0, 0.0, 0.0]
            d[u_axis], d[v_axis] = math.cos(ang), math.sin(ang)
            out += struct.pack("<8f", p[0], p[1], p[2], 0.0, d[0], d[1], d[2], math.inf)
        dest = os.path.join(a.out_dir, f"{name}-inplane.rays")
        with open(dest + ".tmp", "wb") as f:
            f.write(out)
        os.replace(dest + ".tmp", dest)
        print(f"{dest}: {a.count} rays in the plane {'xyz'[k]} = {plane}")


if __name__ == "__main__":
    main()
