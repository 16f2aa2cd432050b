#!/usr/bin/env python3
"""Every real file counted: for each mesh file in ../shared/scenes (all but bad/, whose files are
expected to fail and are tested by test_loader.cpp) and each mesh file the repository's tests hold
(tests/data/meshes, tests/fuzz/seeds, tests/fuzz/regressions), the triangles `arbor info --json`
loads are compared with a count made here from the file itself by a small plain reader per format:

  OBJ   each `f` line of k corners gives k - 2 triangles (none for k < 3);
  PLY   the header, then every record of every element (ASCII or binary of either byte order):
        a `face` list of k indices gives k - 2, a `tristrips` list its strip windows without a
        repeated index (-1 restarts a strip);
  STL   ASCII: the `facet` lines; binary: the count in the header;
  glTF  the default scene's nodes, depth first, each node's mesh's primitives: indices (or
        POSITION) count n gives n / 3 (mode 4), n - 2 (modes 5 and 6, strips and fans), 0 (points
        and lines).

A difference fails, and so does a file arbor refuses unless REFUSED below names it with the reason
(then arbor must refuse it with exit status 1 and one line naming the file, spec/cli.md), and a
file the plain reader cannot count unless UNCOUNTABLE names it. A missing shared folder fails.

    corpus_count_test.py --arbor build/release/apps/arbor/arbor --shared ../shared/scenes --root .
"""
import argparse
import json
import os
import struct
import subprocess
import sys

MESH_EXTENSIONS = {".obj", ".ply", ".stl", ".gltf", ".glb", ".off"}
REPO_FOLDERS = ["tests/data/meshes", "tests/fuzz/seeds/mesh", "tests/fuzz/seeds/obj", "tests/fuzz/regressions/mesh",
                "tests/fuzz/regressions/obj"]

# Files arbor must refuse (path relative to the repository), and why; they are seeds and
# regressions of the loaders' bad-input rows.
REFUSED = {
    "tests/fuzz/seeds/mesh/count-too-big.glb": "accessor count past its buffer view",
    "tests/fuzz/seeds/mesh/count-too-big.ply": "element count larger than the file",
    "tests/fuzz/seeds/mesh/count-too-big.stl": "binary STL count larger than the file",
    "tests/fuzz/seeds/mesh/index-past.glb": "index past the primitive's vertices",
    "tests/fuzz/seeds/mesh/index-past.ply": "face index past the vertex list",
    "tests/fuzz/seeds/mesh/lines.glb": "only lines",
    "tests/fuzz/seeds/mesh/nan.glb": "a NaN vertex",
    "tests/fuzz/seeds/mesh/nan.ply": "a NaN vertex",
    "tests/fuzz/seeds/mesh/nan.stl": "a NaN vertex",
    "tests/fuzz/seeds/mesh/points.ply": "only points",
    "tests/fuzz/seeds/mesh/strips-past.ply": "strip index past the vertex list",
    "tests/fuzz/seeds/mesh/truncated.glb": "GLB cut short",
    "tests/fuzz/seeds/mesh/truncated.ply": "binary PLY body cut short",
    "tests/fuzz/seeds/mesh/truncated.stl": "binary STL cut short",
    "tests/fuzz/regressions/obj/tinyobj-exponent-overflow.obj": "a coordinate out of float range",
}
for _name in ["acc-offset-overread", "anim-cubic-weights-short", "anim-morph-zero-keys", "anim-no-target-node",
              "bad-mimetype", "dup-key-accessors", "fan-2", "image-datauri-nomime", "lineloop-1", "node-dag-blowup",
              "node-extras-deep", "skin-no-ibm", "skin-weights-joints-mismatch", "sparse-indices-no-view",
              "sparse-no-indices", "sparse-strided", "sparse-values-no-view", "strip-1", "target-normal-3",
              "target-position-1", "texture-transform-empty"]:
    REFUSED["tests/fuzz/regressions/mesh/assimp-gltf2-%s.glb" % _name] = "a crafted glTF field Assimp 5.2 trusts (formats.md)"

# Files the plain readers here cannot count, and why (none today).
UNCOUNTABLE = {}


class Uncountable(Exception):
    pass


def count_obj(data):
    n = 0
    for line in data.decode("utf-8", "replace").splitlines():
        tok = line.split()
        if tok and tok[0] == "f":
            n += max(len(tok) - 3, 0)
    return n


PLY_TYPES = {"char": "b", "uchar": "B", "short": "h", "ushort": "H", "int": "i", "uint": "I", "float": "f", "double": "d",
             "int8": "b", "uint8": "B", "int16": "h", "uint16": "H", "int32": "i", "uint32": "I", "float32": "f",
             "float64": "d"}


def strip_count(indices):
    n, strip = 0, []
    for i in list(indices) + [-1]:
        if i == -1:
            n += sum(1 for k in range(len(strip) - 2) if len({strip[k], strip[k + 1], strip[k + 2]}) == 3)
            strip = []
        else:
            strip.append(i)
    return n


def count_ply(data):
    end = data.find(b"end_header")
    if end < 0:
        raise Uncountable("no end_header")
    body = data.index(b"\n", end) + 1
    encoding, elements = None, []
    for line in data[:end].decode("latin-1").splitlines():
        w = line.split()
        if not w:
            continue
        if w[0] == "format":
            encoding = w[1]
        elif w[0] == "element":
            elements.append((w[1], int(w[2]), []))
        elif w[0] == "property":
            elements[-1][2].append((w[2], w[3], w[4]) if w[1] == "list" else (None, w[1], w[2]))
    triangles = 0
    if encoding == "ascii":
        tokens = data[body:].split()
        pos = 0
        for name, count, props in elements:
            if not props:
                continue  # records of no values, however many
            for _ in range(count):
                for count_type, item_type, pname in props:
                    if count_type is None:
                        pos += 1
                        continue
                    k = int(float(tokens[pos]))
                    items = [int(float(t)) for t in tokens[pos + 1:pos + 1 + k]]
                    pos += 1 + k
                    if pname in ("vertex_indices", "vertex_index"):
                        triangles += max(k - 2, 0) if name == "face" else strip_count(items) if name == "tristrips" else 0
        return triangles
    endian = {"binary_little_endian": "<", "binary_big_endian": ">"}.get(encoding)
    if endian is None:
        raise Uncountable("PLY format %r" % encoding)
    pos = body
    for name, count, props in elements:
        if all(c is None for c, _, _ in props):
            pos += count * struct.calcsize(endian + "".join(PLY_TYPES[t] for _, t, _ in props))
            continue
        for _ in range(count):
            for count_type, item_type, pname in props:
                if count_type is None:
                    pos += struct.calcsize(PLY_TYPES[item_type])
                    continue
                (k,) = struct.unpack_from(endian + PLY_TYPES[count_type], data, pos)
                pos += struct.calcsize(PLY_TYPES[count_type])
                fmt = endian + "%d%s" % (k, PLY_TYPES[item_type])
                if pname in ("vertex_indices", "vertex_index"):
                    items = struct.unpack_from(fmt, data, pos)
                    triangles += max(k - 2, 0) if name == "face" else strip_count(items) if name == "tristrips" else 0
                pos += struct.calcsize(fmt)
    return triangles


def count_stl(data):
    if len(data) >= 84 and 84 + 50 * struct.unpack_from("<I", data, 80)[0] == len(data):
        return struct.unpack_from("<I", data, 80)[0]
    return sum(1 for line in data.decode("latin-1").splitlines() if line.split()[:1] == ["facet"])


def count_gltf(data):
    if data[:4] == b"glTF":
        (length,) = struct.unpack_from("<I", data, 12)
        doc = json.loads(data[20:20 + length])
    else:
        doc = json.loads(data)
    accessors, meshes, nodes = doc.get("accessors", []), doc.get("meshes", []), doc.get("nodes", [])
    if "scenes" not in doc:
        raise Uncountable("glTF without scenes")
    roots = doc["scenes"][doc.get("scene", 0)].get("nodes", [])

    def mesh_triangles(m):
        n = 0
        for prim in meshes[m]["primitives"]:
            count = accessors[prim["indices"] if "indices" in prim else prim["attributes"]["POSITION"]]["count"]
            mode = prim.get("mode", 4)
            n += count // 3 if mode == 4 else max(count - 2, 0) if mode in (5, 6) else 0
        return n

    def walk(i):
        node = nodes[i]
        return (mesh_triangles(node["mesh"]) if "mesh" in node else 0) + sum(walk(c) for c in node.get("children", []))

    return sum(walk(r) for r in roots)


def independent_count(path):
    with open(path, "rb") as f:
        data = f.read()
    if data[:4] in (b"ply\n", b"ply\r"):
        return "PLY", count_ply(data)
    if data[:4] == b"glTF":
        return "GLB", count_gltf(data)
    if data.lstrip()[:1] == b"{":
        return "glTF", count_gltf(data)
    if len(data) >= 84 and 84 + 50 * struct.unpack_from("<I", data, 80)[0] == len(data):
        return "STL", count_stl(data)
    if data.lstrip()[:5] == b"solid" and b"facet" in data[:1024]:
        return "STL", count_stl(data)
    if path.lower().endswith(".off"):
        raise Uncountable("OFF is not read by arbor")
    return "OBJ", count_obj(data)


def corpus(shared, root):
    files = []
    for dirpath, dirnames, names in os.walk(shared):
        dirnames[:] = sorted(d for d in dirnames if d != "bad")
        files += [os.path.join(dirpath, n) for n in sorted(names) if os.path.splitext(n)[1].lower() in MESH_EXTENSIONS]
    shared_count = len(files)
    for folder in REPO_FOLDERS:
        d = os.path.join(root, folder)
        if os.path.isdir(d):
            files += [os.path.join(d, n) for n in sorted(os.listdir(d)) if os.path.isfile(os.path.join(d, n))]
    return files, shared_count


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--arbor", required=True)
    ap.add_argument("--shared", required=True, help="the shared/scenes folder (ARBOR_SHARED_SCENES)")
    ap.add_argument("--root", required=True, help="the repository")
    a = ap.parse_args()
    if not os.path.isdir(os.path.join(a.shared, "models")):
        print("FAIL: %s/models not found: the corpus check needs ../shared/scenes (set ARBOR_SHARED_SCENES)" % a.shared)
        return 1
    files, shared_count = corpus(a.shared, a.root)
    if shared_count == 0:
        print("FAIL: no mesh file under %s" % a.shared)
        return 1
    failures, formats, refused = [], {}, 0
    seen_refused = set()
    for path in files:
        rel = os.path.relpath(path, a.root)
        run = subprocess.run([a.arbor, "info", "--json", path], capture_output=True, text=True)
        if rel in REFUSED:
            seen_refused.add(rel)
            lines = run.stderr.strip().splitlines()
            if run.returncode != 1 or len(lines) != 1 or path not in lines[0]:
                failures.append("%s: expected a refusal (%s): exit %d, stderr %r" % (rel, REFUSED[rel], run.returncode, run.stderr))
            else:
                refused += 1
                print("refused  %-60s %s" % (rel, lines[0].partition(path + ":")[2].strip()))
            continue
        if run.returncode != 0:
            failures.append("%s: arbor refused it (exit %d): %s" % (rel, run.returncode, run.stderr.strip()))
            continue
        got = json.loads(run.stdout)["triangles"]
        try:
            fmt, want = independent_count(path)
        except (Uncountable, ValueError, KeyError, IndexError, struct.error) as e:
            if rel in UNCOUNTABLE:
                print("excluded %-60s %s" % (rel, UNCOUNTABLE[rel]))
            else:
                failures.append("%s: the plain reader cannot count it (%s: %s)" % (rel, type(e).__name__, e))
            continue
        formats[fmt] = formats.get(fmt, 0) + 1
        status = "ok" if got == want else "DIFFERS"
        print("%-8s %-60s %-4s arbor %d, plain reader %d" % (status, rel, fmt, got, want))
        if got != want:
            failures.append("%s: arbor loads %d triangles, the plain reader counts %d" % (rel, got, want))
    for rel in sorted(set(REFUSED) - seen_refused):
        failures.append("%s: listed in REFUSED but not found" % rel)
    counted = sum(formats.values())
    print("%d files: %d counted (%s; %d from the shared scenes), %d refused as expected" % (
        len(files), counted, ", ".join("%s %d" % kv for kv in sorted(formats.items())), shared_count, refused))
    for f in failures:
        print("FAIL: " + f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
