#!/usr/bin/env python3
"""Seed corpora for scripts/fuzz.sh: OBJ seeds cut from the shared models (the first vertices and
the faces that use only them) and ray/hit files covering the stiff cases of spec/rayfile.md."""
import math
import os
import struct
import sys


def model_heads(models_dir, out_dir, vertices=40):
    for name in sorted(os.listdir(models_dir)):
        if not name.endswith(".obj"):
            continue
        v_lines, other, faces = [], [], []
        with open(os.path.join(models_dir, name), errors="replace") as f:
            for line in f:
                tok = line.split()
                if not tok:
                    continue
                if tok[0] == "v" and len(v_lines) < vertices:
                    v_lines.append(line)
                elif tok[0] in ("vt", "vn") and len(other) < vertices:
                    other.append(line)
                elif tok[0] == "f" and len(faces) < 30:
                    idx = [int(t.split("/")[0]) for t in tok[1:]]
                    if all(0 < i <= vertices for i in idx):
                        faces.append(" ".join(["f"] + [t.split("/")[0] for t in tok[1:]]) + "\n")
        if faces:
            with open(os.path.join(out_dir, "head-" + name), "w") as out:
                out.writelines(v_lines + other + faces)


def ray_file(path, rays, magic=b"RAYS", version=1, count=None):
    with open(path, "wb") as f:
        f.write(magic + struct.pack("<IQ", version, len(rays) if count is None else count))
        for r in rays:
            f.write(struct.pack("<8f", *r))


def ray_seeds(out_dir):
    inf, nan = math.inf, math.nan
    normal = [(0.1 * i, 0.2, 5.0, 0.0, 0.01 * i, -0.02, -1.0, inf) for i in range(8)]
    axis = [(0.5, 0.0, 5.0, 0.0, 0.0, -0.0, -1.0, inf), (0.0, -3.0, 0.0, 0.0, -0.0, 1.0, 0.0, inf),
            (-4.0, 0.0, 0.0, 0.0, 1.0, 0.0, -0.0, inf), (0.0, 2.0, 0.0, 0.0, 0.0, 0.0, 1.0, inf)]
    bad = [(nan, 0, 5, 0, 0, 0, -1, inf), (0, 0, 5, nan, 0, 0, -1, inf), (0, 0, 5, 0, 0, 0, -1, nan),
           (0, 0, 5, 0, 0, 0, 0, inf), (0, 0, 5, 0, inf, 0, -1, inf), (0, 0, 5, 2, 0, 0, -1, 1)]
    extreme = [(0, 0, 5, -inf, 0, 0, -1, inf), (0, 0, 5, 0, 0, 0, -1e-30, inf), (0, 0, 5, 0, 0, 0, -1e30, inf),
               (0, 0, 1, 0, 0, 0, 1, inf), (3e38, 3e38, 3e38, 0, -1, -1, -1, inf), (0, 0, 5, 4, 0, 0, -1, 4)]
    ray_file(os.path.join(out_dir, "normal.rays"), normal)
    ray_file(os.path.join(out_dir, "axis.rays"), axis)
    ray_file(os.path.join(out_dir, "nonfinite.rays"), bad)
    ray_file(os.path.join(out_dir, "extreme.rays"), extreme)
    ray_file(os.path.join(out_dir, "empty.rays"), [])
    ray_file(os.path.join(out_dir, "count-too-big.rays"), normal[:2], count=3)
    ray_file(os.path.join(out_dir, "version2.rays"), normal[:1], version=2)
    with open(os.path.join(out_dir, "one.hits"), "wb") as f:
        f.write(b"HITS" + struct.pack("<IQ", 1, 2) + struct.pack("<fIff", 1.5, 3, 0.25, 0.5)
                + struct.pack("<fIff", inf, 0xFFFFFFFF, 0, 0))


if __name__ == "__main__":
    kind, out = sys.argv[1], sys.argv[2]
    os.makedirs(out, exist_ok=True)
    if kind == "obj":
        model_heads(sys.argv[3], out)
    else:
        ray_seeds(out)
