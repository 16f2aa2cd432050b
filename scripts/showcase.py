#!/usr/bin/env python3
"""Files for the renders of other formats in docs/formats.md, made from the shared OBJ models:

  OUT/bunny.ply   the Stanford bunny as a binary little-endian PLY with positions and faces only,
                  as the Stanford repository publishes its scans (no normals: render with --smooth)
  OUT/spot.glb    Keenan Crane's spot as a binary glTF 2.0: positions, normals (area-weighted),
                  its texture coordinates, and a procedural base colour texture embedded as PNG:
                  an 8 x 8 checkerboard running from red at the image's top to blue at its bottom,
                  an "F" in every light square (mirrored or upside-down F's would show a flip)

usage: scripts/showcase.py MODELS_DIR OUT_DIR   (then the commands in docs/formats.md)
"""
import json
import math
import os
import struct
import sys
import zlib


def read_obj(path):
    v, vt, faces = [], [], []
    with open(path) as f:
        for line in f:
            t = line.split()
            if not t:
                continue
            if t[0] == "v":
                v.append(tuple(float(x) for x in t[1:4]))
            elif t[0] == "vt":
                vt.append((float(t[1]), float(t[2])))
            elif t[0] == "f":
                corners = [(int(c.split("/")[0]) - 1, int(c.split("/")[1]) - 1 if "/" in c and c.split("/")[1] else -1)
                           for c in t[1:]]
                for k in range(1, len(corners) - 1):  # the shared models' polygons are convex
                    faces.append((corners[0], corners[k], corners[k + 1]))
    return v, vt, faces


def write_ply(path, v, faces):
    head = ("ply\nformat binary_little_endian 1.0\ncomment made by arbor scripts/showcase.py\n"
            "element vertex %d\nproperty float x\nproperty float y\nproperty float z\n"
            "element face %d\nproperty list uchar int vertex_indices\nend_header\n" % (len(v), len(faces)))
    with open(path, "wb") as f:
        f.write(head.encode())
        f.write(b"".join(struct.pack("<3f", *p) for p in v))
        f.write(b"".join(struct.pack("<B3i", 3, a[0], b[0], c[0]) for a, b, c in faces))


def png(width, height, pixel):
    rows = b"".join(b"\0" + bytes(c for x in range(width) for c in pixel(x, y)) for y in range(height))
    chunk = lambda t, d: struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d) & 0xFFFFFFFF)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(rows, 9)) + chunk(b"IEND", b""))


def texture(size=512):
    cell = size // 8

    def pixel(x, y):
        top = 1.0 - y / (size - 1)  # 1 at the image's top row
        light = ((x // cell) + (y // cell)) % 2 == 0
        base = (int(40 + 200 * top), 60, int(40 + 200 * (1 - top)))
        if not light:
            return tuple(c // 3 for c in base)
        # An "F" in the light squares: a stem on the left, bars at the top and the middle.
        cx, cy = (x % cell) / cell, (y % cell) / cell
        stem = 0.3 < cx < 0.42 and 0.2 < cy < 0.8
        bar = 0.3 < cx < 0.72 and 0.2 < cy < 0.3 or 0.3 < cx < 0.62 and 0.45 < cy < 0.55
        return (250, 250, 250) if stem or bar else base
    return png(size, size, pixel)


def write_glb(path, v, vt, faces):
    # glTF attributes are per vertex: one vertex per (position, texture coordinate) pair.
    normals = [[0.0, 0.0, 0.0] for _ in v]
    for a, b, c in faces:
        p0, p1, p2 = v[a[0]], v[b[0]], v[c[0]]
        e1 = [p1[i] - p0[i] for i in range(3)]
        e2 = [p2[i] - p0[i] for i in range(3)]
        n = [e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]]
        for corner in (a, b, c):
            for i in range(3):
                normals[corner[0]][i] += n[i]
    ids, verts, indices = {}, [], []
    for face in faces:
        for corner in face:
            if corner not in ids:
                ids[corner] = len(verts)
                verts.append(corner)
            indices.append(ids[corner])
    pos = b"".join(struct.pack("<3f", *v[p]) for p, _ in verts)
    nor = b""
    for p, _ in verts:
        n = normals[p]
        length = math.sqrt(sum(c * c for c in n)) or 1.0
        nor += struct.pack("<3f", *(c / length for c in n))
    uv = b"".join(struct.pack("<2f", vt[t][0], 1.0 - vt[t][1]) for _, t in verts)  # glTF's v runs down
    idx = b"".join(struct.pack("<I", i) for i in indices)
    image = texture()
    buf, views = b"", []
    for blob in (pos, nor, uv, idx, image):
        buf += b"\0" * (-len(buf) % 4)
        views.append({"buffer": 0, "byteOffset": len(buf), "byteLength": len(blob)})
        buf += blob
    buf += b"\0" * (-len(buf) % 4)
    lo = [min(v[p][i] for p, _ in verts) for i in range(3)]
    hi = [max(v[p][i] for p, _ in verts) for i in range(3)]
    doc = {"asset": {"version": "2.0", "generator": "arbor scripts/showcase.py"}, "scene": 0,
           "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0, "name": "spot"}],
           "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2}, "indices": 3,
                                       "material": 0}]}],
           "materials": [{"name": "checker", "pbrMetallicRoughness": {"baseColorTexture": {"index": 0},
                                                                      "metallicFactor": 0.0}}],
           "textures": [{"source": 0}], "images": [{"bufferView": 4, "mimeType": "image/png"}],
           "accessors": [{"bufferView": 0, "componentType": 5126, "count": len(verts), "type": "VEC3", "min": lo, "max": hi},
                         {"bufferView": 1, "componentType": 5126, "count": len(verts), "type": "VEC3"},
                         {"bufferView": 2, "componentType": 5126, "count": len(verts), "type": "VEC2"},
                         {"bufferView": 3, "componentType": 5125, "count": len(indices), "type": "SCALAR"}],
           "bufferViews": views, "buffers": [{"byteLength": len(buf)}]}
    j = json.dumps(doc).encode()
    j += b" " * (-len(j) % 4)
    with open(path, "wb") as f:
        f.write(b"glTF" + struct.pack("<II", 2, 12 + 8 + len(j) + 8 + len(buf)) + struct.pack("<I", len(j)) + b"JSON" + j
                + struct.pack("<I", len(buf)) + b"BIN\0" + buf)


def main():
    models, out = sys.argv[1], sys.argv[2]
    os.makedirs(out, exist_ok=True)
    v, _, faces = read_obj(os.path.join(models, "stanford-bunny.obj"))
    write_ply(os.path.join(out, "bunny.ply"), v, faces)
    v, vt, faces = read_obj(os.path.join(models, "spot.obj"))
    if not vt or any(c[1] < 0 for f in faces for c in f):
        sys.exit("spot.obj has no texture coordinates on every corner")
    write_glb(os.path.join(out, "spot.glb"), v, vt, faces)
    print("wrote", os.path.join(out, "bunny.ply"), "and", os.path.join(out, "spot.glb"))


if __name__ == "__main__":
    main()
