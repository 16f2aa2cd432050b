"""Meshes for the peers benchmark: a plain OBJ reader (positions and faces, polygons split into
fans), so that every library gets the very same float32 vertices and uint32 faces, and the edge
facts the queries need (interior edges, whether the mesh is closed)."""
import numpy as np


def read_obj(path, dtype=np.float32):
    """(V, 3) vertices (float32 unless `dtype`) and (F, 3) uint32 faces of an OBJ file (v and f lines only)."""
    verts, faces = [], []
    with open(path) as f:
        for line in f:
            if line.startswith("v "):
                verts.append([float(x) for x in line.split()[1:4]])
            elif line.startswith("f "):
                idx = [int(tok.split("/")[0]) for tok in line.split()[1:]]
                idx = [i - 1 if i > 0 else len(verts) + i for i in idx]
                for k in range(1, len(idx) - 1):
                    faces.append([idx[0], idx[k], idx[k + 1]])
    return np.asarray(verts, dtype), np.asarray(faces, np.uint32)


def edges(faces):
    """Unique undirected edges (E, 2) and how many faces share each."""
    f = faces.astype(np.int64)
    e = np.sort(np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]]), axis=1)
    return np.unique(e, axis=0, return_counts=True)


def is_closed(faces):
    """Every edge shared by exactly two faces: inside/outside is defined by crossing parity."""
    _, count = edges(faces)
    return bool((count == 2).all())


def interior_edges(faces):
    """Edges shared by exactly two faces, (E, 2), and the third vertex of each face, (E, 2)."""
    f = faces.astype(np.int64)
    e = np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]])
    third = np.concatenate([f[:, 2], f[:, 0], f[:, 1]])
    e = np.sort(e, axis=1)
    order = np.lexsort((e[:, 1], e[:, 0]))
    e, third = e[order], third[order]
    _, start, count = np.unique(e, axis=0, return_index=True, return_counts=True)
    pair = start[count == 2]
    return e[pair], np.stack([third[pair], third[pair + 1]], axis=1)


def diagonal(verts):
    return float(np.linalg.norm(verts.max(axis=0).astype(np.float64) - verts.min(axis=0)))


def unit_cube():
    """The closed unit cube [0, 1]^3: 8 float32 corners, 12 uint32 triangles turning outwards."""
    v = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)], np.float32)
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    return v, np.array([t for a, b, c, d in quads for t in ((a, b, c), (a, c, d))], np.uint32)
