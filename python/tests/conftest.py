"""Shared fixtures of the pytest suite (run by ctest: `python` in the release build)."""
import os
import pathlib

import numpy as np
import pytest

import arbor
import deform


def shared_models():
    """The shared test models; the suite fails (not skips) without them."""
    root = os.environ.get("ARBOR_SHARED_SCENES") or str(pathlib.Path(__file__).resolve().parents[2] / ".." / "shared" / "scenes")
    models = sorted(pathlib.Path(root, "models").resolve().glob("*.obj"))
    assert len(models) >= 10, f"the shared models are needed: {root}/models holds {len(models)} .obj files"
    return models


@pytest.fixture(scope="session")
def models():
    return shared_models()


@pytest.fixture(scope="session")
def spot(models):
    return next(m for m in models if m.name == "spot.obj")


def read_obj(path):
    """Vertices (float32) and fan-triangulated faces (int64) of an OBJ file (deform.read_obj)."""
    return deform.read_obj(path, np.int64)


def box_mesh(lo=(-1.0, -1.0, -1.0), hi=(1.0, 1.0, 1.0)):
    """A closed box: 8 vertices, 12 outward triangles."""
    x0, y0, z0 = lo
    x1, y1, z1 = hi
    v = np.array([[x0, y0, z0], [x1, y0, z0], [x1, y1, z0], [x0, y1, z0],
                  [x0, y0, z1], [x1, y0, z1], [x1, y1, z1], [x0, y1, z1]], dtype=np.float32)
    f = np.array([[0, 2, 1], [0, 3, 2], [4, 5, 6], [4, 6, 7], [0, 1, 5], [0, 5, 4],
                  [2, 3, 7], [2, 7, 6], [1, 2, 6], [1, 6, 5], [0, 4, 7], [0, 7, 3]], dtype=np.int32)
    return v, f


def random_rays(scene, n, seed=1):
    """Rays from a sphere around the scene towards random points inside its box."""
    rng = np.random.default_rng(seed)
    lo, hi = scene.bounds
    c, r = (lo + hi) / 2, np.linalg.norm(hi - lo)
    d = rng.normal(size=(n, 3))
    o = c + r * d / np.linalg.norm(d, axis=1, keepdims=True)
    t = lo + rng.random((n, 3)) * (hi - lo)
    return o.astype(np.float32), (t - o).astype(np.float32)


@pytest.fixture
def box_scene():
    v, f = box_mesh()
    s = arbor.Scene(v, f)
    s.build("bvh-sah")
    return s
