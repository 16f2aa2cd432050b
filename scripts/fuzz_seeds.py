#!/usr/bin/env python3
"""Seed corpora for scripts/fuzz.sh: OBJ seeds cut from the shared models (the first vertices and
the faces that use only them), ray/hit files covering the stiff cases of spec/rayfile.md, and small
PLY, STL, glTF and GLB files, good and broken (the bad-input rows of the loader tests)."""
import base64
import json
import math
import os
import struct
import sys
import zlib


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


def ply(vertices, faces, encoding="ascii", normals=None, colours=None, count_override=None):
    endian = {"binary_little_endian": "<", "binary_big_endian": ">"}.get(encoding)
    head = "ply\nformat %s 1.0\nelement vertex %d\nproperty float x\nproperty float y\nproperty float z\n" % (
        encoding, count_override or len(vertices))
    if normals:
        head += "property float nx\nproperty float ny\nproperty float nz\n"
    if colours:
        head += "property uchar red\nproperty uchar green\nproperty uchar blue\n"
    head += "element face %d\nproperty list uchar int vertex_indices\nend_header\n" % len(faces)
    body = b""
    for i, v in enumerate(vertices):
        vals = list(v) + (list(normals[i]) if normals else [])
        if endian:
            body += struct.pack(endian + "%df" % len(vals), *vals)
            if colours:
                body += bytes(colours[i])
        else:
            body += (" ".join("%g" % x for x in vals) + ("".join(" %d" % c for c in colours[i]) if colours else "") + "\n").encode()
    for f in faces:
        body += (struct.pack(endian + "B%di" % len(f), len(f), *f) if endian
                 else ("%d %s\n" % (len(f), " ".join(map(str, f)))).encode())
    return head.encode() + body


def ply_strips(vertices, strips, encoding="ascii", header_extra="", elements=""):
    """PLY with a tristrips element: one vertex_indices list per strip record, -1 restarts."""
    endian = {"binary_little_endian": "<", "binary_big_endian": ">"}.get(encoding)
    head = "ply\nformat %s 1.0\n%selement vertex %d\nproperty float x\nproperty float y\nproperty float z\n" % (
        encoding, header_extra, len(vertices))
    head += "element tristrips %d\nproperty list int int vertex_indices\n%send_header\n" % (len(strips), elements)
    body = b""
    for v in vertices:
        body += struct.pack(endian + "3f", *v) if endian else ("%g %g %g\n" % v).encode()
    for s in strips:
        body += (struct.pack(endian + "i%di" % len(s), len(s), *s) if endian
                 else ("%d %s\n" % (len(s), " ".join(map(str, s)))).encode())
    return head.encode() + body


def stl_binary(triangles, count=None):
    out = b"binary STL seed".ljust(80, b" ") + struct.pack("<I", len(triangles) if count is None else count)
    for t in triangles:
        out += struct.pack("<12fH", 0, 0, 1, *t[0], *t[1], *t[2], 0)
    return out


def stl_ascii(triangles):
    out = "solid seed\n"
    for t in triangles:
        out += "facet normal 0 0 1\n outer loop\n" + "".join("  vertex %g %g %g\n" % p for p in t) + " endloop\nendfacet\n"
    return (out + "endsolid seed\n").encode()


def png(w, h, rows):
    raw = b"".join(b"\0" + bytes(c for px in row for c in px) for row in rows)
    chunk = lambda t, d: struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d) & 0xFFFFFFFF)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))


def gltf(vertices, indices, glb=True, mode=4, position_count=None, index_count=None, matrix=None):
    blobs = [b"".join(struct.pack("<3f", *v) for v in vertices),
             b"".join(struct.pack("<3f", 0, 0, 1) for _ in vertices),
             b"".join(struct.pack("<2f", v[0], v[1]) for v in vertices),
             b"".join(struct.pack("<I", i) for i in indices),
             png(2, 2, [[(255, 0, 0), (255, 0, 0)], [(0, 0, 255), (0, 0, 255)]])]
    buf, views = b"", []
    for b in blobs:
        buf += b"\0" * (-len(buf) % 4)
        views.append({"buffer": 0, "byteOffset": len(buf), "byteLength": len(b)})
        buf += b
    buf += b"\0" * (-len(buf) % 4)
    acc = [{"bufferView": 0, "componentType": 5126, "count": position_count or len(vertices), "type": "VEC3",
            "min": [min(v[k] for v in vertices) for k in range(3)], "max": [max(v[k] for v in vertices) for k in range(3)]},
           {"bufferView": 1, "componentType": 5126, "count": len(vertices), "type": "VEC3"},
           {"bufferView": 2, "componentType": 5126, "count": len(vertices), "type": "VEC2"},
           {"bufferView": 3, "componentType": 5125, "count": index_count or len(indices), "type": "SCALAR"}]
    node = {"mesh": 0}
    if matrix:
        node["matrix"] = matrix
    doc = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [node],
           "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2}, "indices": 3,
                                       "material": 0, "mode": mode}]}],
           "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicFactor": 0}}],
           "textures": [{"source": 0}], "images": [{"bufferView": 4, "mimeType": "image/png"}],
           "accessors": acc, "bufferViews": views, "buffers": [{"byteLength": len(buf)}]}
    if not glb:
        doc["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64.b64encode(buf).decode()
        return json.dumps(doc).encode()
    j = json.dumps(doc).encode()
    j += b" " * (-len(j) % 4)
    return (b"glTF" + struct.pack("<II", 2, 12 + 8 + len(j) + 8 + len(buf)) + struct.pack("<I", len(j)) + b"JSON" + j
            + struct.pack("<I", len(buf)) + b"BIN\0" + buf)


def rich_gltf(kind):
    """A valid quad GLB using one of the glTF features Assimp 5.2 trusts the fields of (checked by
    engine/formats/gltf_structure.cpp): the fuzzer starts from each and mutates those fields."""
    buf = b"".join(struct.pack("<3f", *p) for p in [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)])  # 0: positions
    buf += b"".join(struct.pack("<3f", 0, 0, 1) for _ in range(4))                             # 48: normals
    buf += b"".join(struct.pack("<H", i) for i in [0, 1, 2, 0, 2, 3])                          # 96: indices
    buf += struct.pack("<I", 2) + struct.pack("<3f", 1, 2, 0)                                  # 108: sparse
    buf += b"".join(struct.pack("<f", 1.0 if k % 5 == 0 else 0.0) for k in range(16))          # 124: matrix
    buf += b"".join(struct.pack("<4f", 1, 0, 0, 0) for _ in range(4))                          # 188: weights
    buf += bytes(16)                                                                            # 252: joints
    buf += struct.pack("<3f", 0, 0.5, 1)                                                       # 268: key times
    view = lambda off, n, **kw: dict(buffer=0, byteOffset=off, byteLength=n, **kw)
    acc = lambda v, ct, n, t, **kw: dict(bufferView=v, componentType=ct, count=n, type=t, **kw)
    doc = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
           "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2}]}],
           "accessors": [acc(0, 5126, 4, "VEC3", min=[0, 0, 0], max=[1, 1, 0]), acc(1, 5126, 4, "VEC3"), acc(2, 5123, 6, "SCALAR")],
           "bufferViews": [view(0, 48), view(48, 48), view(96, 12), view(108, 4), view(112, 12), view(124, 64), view(188, 64),
                           view(252, 16), view(268, 12)],
           "buffers": [{"byteLength": len(buf)}]}
    prim = doc["meshes"][0]["primitives"][0]
    if kind == "sparse":
        doc["accessors"][0]["sparse"] = {"count": 1, "indices": {"bufferView": 3, "componentType": 5125}, "values": {"bufferView": 4}}
        doc["accessors"][0]["max"] = [1, 2, 0]
    elif kind == "skin":
        doc["accessors"] += [acc(5, 5126, 1, "MAT4"), acc(6, 5126, 4, "VEC4"), acc(7, 5121, 4, "VEC4")]
        prim["attributes"].update({"WEIGHTS_0": 4, "JOINTS_0": 5})
        doc["nodes"] = [{"children": [1], "extras": {"rig": {"bones": [1, 2]}}}, {"mesh": 0, "skin": 0}]
        doc["skins"] = [{"joints": [0], "inverseBindMatrices": 3}]
    elif kind == "animation":
        doc["accessors"] += [acc(8, 5126, 3, "SCALAR"), acc(1, 5126, 3, "VEC3"), acc(8, 5126, 1, "SCALAR")]
        doc["nodes"] = [{"children": [1]}, {"mesh": 0, "translation": [0, 0, 1]}]
        doc["animations"] = [{"samplers": [{"input": 3, "output": 4}, {"input": 5, "output": 1, "interpolation": "CUBICSPLINE"}],
                              "channels": [{"sampler": 0, "target": {"node": 1, "path": "translation"}},
                                           {"sampler": 1, "target": {"node": 0, "path": "scale"}}]}]
    elif kind == "morph":
        prim["targets"] = [{"POSITION": 1, "NORMAL": 1}]
        doc["meshes"][0]["weights"] = [0.5]
        doc["accessors"].append(acc(2, 5123, 4, "SCALAR"))
        doc["meshes"][0]["primitives"].append({"attributes": {"POSITION": 0}, "indices": 3, "mode": 6})
        doc["meshes"][0]["primitives"].append({"attributes": {"POSITION": 0}, "indices": 3, "mode": 2})
    elif kind == "texture-transform":
        doc["extensionsUsed"] = ["KHR_texture_transform"]
        doc["materials"] = [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0, "extensions": {
            "KHR_texture_transform": {"offset": [0.5, 0], "scale": [2, 2], "rotation": 1}}}}}]
        doc["textures"] = [{"source": 0, "sampler": 0}]
        doc["samplers"] = [{"wrapS": 33071}]
        doc["images"] = [{"uri": "data:image/png;base64," + base64.b64encode(png(1, 1, [[(9, 9, 9)]])).decode()}]
        prim["material"] = 0
    j = json.dumps(doc).encode()
    j += b" " * (-len(j) % 4)
    buf += b"\0" * (-len(buf) % 4)
    return (b"glTF" + struct.pack("<II", 2, 12 + 8 + len(j) + 8 + len(buf)) + struct.pack("<I", len(j)) + b"JSON" + j
            + struct.pack("<I", len(buf)) + b"BIN\0" + buf)


def mesh_seeds(out_dir):
    nan = math.nan
    v = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0.5, 0.5, 1)]
    f = [(0, 1, 2, 3), (0, 1, 4), (1, 2, 4)]
    n = [(0, 0, 1)] * 5
    c = [(255, 0, 0), (0, 255, 0), (0, 0, 255), (255, 255, 255), (10, 20, 30)]
    tri = [((0, 0, 0), (1, 0, 0), (0, 1, 0)), ((1, 0, 0), (1, 1, 0), (0, 1, 0))]
    seeds = {
        "ascii.ply": ply(v, f, normals=n, colours=c),
        "le.ply": ply(v, f, "binary_little_endian", normals=n, colours=c),
        "be.ply": ply(v, f, "binary_big_endian"),
        "concave.ply": ply([(0, 0, 0), (2, 0, 0), (2, 1, 0), (1, 1, 0), (1, 2, 0), (0, 2, 0)], [(0, 1, 2, 3, 4, 5)]),
        "truncated.ply": ply(v, f, "binary_little_endian")[:-7],
        "count-too-big.ply": ply(v, f, "binary_little_endian", count_override=900000000),
        "index-past.ply": ply(v, [(0, 1, 9)], "binary_little_endian"),
        "nan.ply": ply([(0, 0, 0), (nan, 0, 0), (0, 1, 0)], [(0, 1, 2)], "binary_little_endian"),
        "points.ply": ply(v, []),
        "strips-be.ply": ply_strips(v, [[0, 1, 3, 2, 2, 4, -1, 1, 2, 4]], "binary_big_endian"),
        "strips-past.ply": ply_strips(v, [[0, 1, 3, 7]], "binary_little_endian"),
        "blender-header.ply": ply_strips(v, [[0, 1, 3, 2]], header_extra="Created by Blender3D 247 - www.blender.org\n"),
        "binary.stl": stl_binary(tri),
        "ascii.stl": stl_ascii(tri),
        "truncated.stl": stl_binary(tri)[:-10],
        "count-too-big.stl": stl_binary(tri, count=1000000),
        "nan.stl": stl_binary([((0, 0, 0), (nan, 0, 0), (0, 1, 0))]),
        "quad.glb": gltf(v[:4], [0, 1, 2, 0, 2, 3]),
        "quad.gltf": gltf(v[:4], [0, 1, 2, 0, 2, 3], glb=False, matrix=[2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 2, 0, 1, 0, 0, 1]),
        "strip.glb": gltf(v[:4], [0, 1, 3, 2], mode=5),
        "lines.glb": gltf(v[:4], [0, 1, 1, 2], mode=1),
        "truncated.glb": gltf(v[:4], [0, 1, 2, 0, 2, 3])[:-60],
        "count-too-big.glb": gltf(v[:4], [0, 1, 2, 0, 2, 3], position_count=100000),
        "index-past.glb": gltf(v[:4], [0, 1, 2, 0, 2, 9]),
        "nan.glb": gltf([(0, 0, 0), (nan, 0, 0), (1, 1, 0), (0, 1, 0)], [0, 1, 2, 0, 2, 3]),
    }
    for kind in ("sparse", "skin", "animation", "morph", "texture-transform"):
        seeds["rich-" + kind + ".glb"] = rich_gltf(kind)
    for name, data in seeds.items():
        with open(os.path.join(out_dir, name), "wb") as out:
            out.write(data)


if __name__ == "__main__":
    kind, out = sys.argv[1], sys.argv[2]
    os.makedirs(out, exist_ok=True)
    if kind == "obj":
        model_heads(sys.argv[3], out)
    elif kind == "mesh":
        mesh_seeds(out)
    else:
        ray_seeds(out)
