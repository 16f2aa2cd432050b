"""The deforming model of the update tests (test_update.py), which scripts/bench_refit.py deforms
too: a mesh read from an OBJ file and moved by travelling sine waves, the same waves as
tests/deform.h. Here, beside the tests, so that the suite's copy (tests/python_package_test.sh)
carries it."""
import numpy as np


def read_obj(path, index_dtype=np.uint32):
    """Vertices (float32) and fan-triangulated faces (index_dtype) of an OBJ file (v and f lines only)."""
    v, f = [], []
    for line in open(path):
        p = line.split()
        if not p:
            continue
        if p[0] == "v":
            v.append([float(x) for x in p[1:4]])
        elif p[0] == "f":
            idx = [int(q.split("/")[0]) for q in p[1:]]
            idx = [i - 1 if i > 0 else len(v) + i for i in idx]
            f.extend([idx[0], idx[k], idx[k + 1]] for k in range(1, len(idx) - 1))
    return np.array(v, dtype=np.float32), np.array(f, dtype=index_dtype)


def pose(rest, step, amplitude=0.04):
    """The rest positions displaced by travelling sine waves of `amplitude` times the box's diagonal
    (as tests/deform.h), at time `step`."""
    diag = float(np.linalg.norm(rest.max(axis=0) - rest.min(axis=0)))
    a = amplitude * diag
    out = rest.copy()
    out[:, 0] += a * np.sin(6 * np.pi * rest[:, 1] / diag + 0.9 * step)
    out[:, 2] += a * np.cos(4 * np.pi * rest[:, 0] / diag + 0.6 * step)
    return out
