"""The queries of the peers benchmark, made once per model and given to every library alike.

  camera: `arbor rays --kind primary` with a held-out view (--view-seed), the rays a renderer casts;
  random: `arbor rays --kind random`, origins and directions anywhere in the scene box;
  edge:   rays aimed at points on interior edges (shared by two faces) from far away, where leaky
          tests lose hits: where the two faces lie on either side of the plane through the ray and
          the edge, the ray pierces the surface there and must hit one of them (at the latest);
          where both lie on one side, it grazes an outline and the smallest change decides, so
          those rays are returned as `grazing` and the referee leaves them out;
  shadow: `arbor rays --kind shadow`, any-hit rays from surface points to the light, given with
          their direction scaled by tfar so that every ray runs over t in [0, 1] (Open3D takes one
          tnear and tfar for all rays);
  points: uniform in the scene box grown by 10 % on each side, for closest point and inside.
"""
import os
import subprocess
import tempfile

import numpy as np

from . import meshes


def arbor_rays(arbor_cmd, model, kind, count, seed):
    """origins, directions, tnear, tfar of `arbor rays` (the .rays file of spec/rayfile.md)."""
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "r.rays")
        subprocess.run([arbor_cmd, "rays", "--scene", model, "--kind", kind, "--count", str(count),
                        "--seed", str(seed), "--view-seed", str(seed + 1000), "-o", out],
                       check=True, capture_output=True)
        import arbor
        return arbor.read_rays(out)


def edge_rays(verts, faces, count, seed):
    rng = np.random.default_rng(seed)
    e, third = meshes.interior_edges(faces)
    chosen = rng.integers(0, len(e), count)
    pick = e[chosen]
    s = rng.uniform(0.2, 0.8, count)[:, None]
    a, b = verts[pick[:, 0]].astype(np.float64), verts[pick[:, 1]].astype(np.float64)
    target = a + s * (b - a)
    centre = (verts.max(axis=0).astype(np.float64) + verts.min(axis=0)) / 2
    u = rng.normal(size=(count, 3))
    u /= np.linalg.norm(u, axis=1, keepdims=True)
    origins = (centre + 2.0 * meshes.diagonal(verts) * u).astype(np.float32)
    directions = (target - origins).astype(np.float32)
    v = verts.astype(np.float64)
    n = np.cross(directions.astype(np.float64), b - a)
    side = [np.einsum("ij,ij->i", n, v[third[chosen, k]] - a) for k in (0, 1)]
    grazing = side[0] * side[1] >= 0
    rays = origins, directions, np.zeros(count, np.float32), np.full(count, np.inf, np.float32)
    return rays, grazing


def unit_tfar(origins, directions, tnear, tfar):
    """The same segments with t in [tnear/tfar, 1]: direction scaled by tfar."""
    finite = np.isfinite(tfar)
    scale = np.where(finite, tfar, 1.0).astype(np.float32)
    return origins, directions * scale[:, None], np.where(finite, tnear / scale, tnear), np.where(finite, 1.0, np.inf).astype(np.float32)


def box_points(verts, count, seed):
    rng = np.random.default_rng(seed)
    lo, hi = verts.min(axis=0).astype(np.float64), verts.max(axis=0).astype(np.float64)
    pad = 0.1 * (hi - lo)
    return rng.uniform(lo - pad, hi + pad, (count, 3)).astype(np.float32)
