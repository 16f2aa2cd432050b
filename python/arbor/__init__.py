"""arbor: ray queries on triangle meshes, on numpy arrays.

    scene = arbor.Scene.load("bunny.obj")            # or arbor.Scene(vertices, faces)
    scene.build("bvh-sah")                           # or "auto" (the default), "lbvh", ...
    hits = scene.intersect(origins, directions)      # structured array: t, geom, prim, u, v
    occ = scene.occluded(origins, directions)        # bool per ray
    scene.intersect(origins, directions, out=hits)   # into an array of the caller's (reused)
    hits = scene.intersect(origins, directions, normals=True)   # also the unit normal
    hits, counts = scene.intersect_all(origins, directions, max_hits=16)
    near = scene.closest_point(points)               # distance, geom, prim, point, u, v
    ins = scene.inside(points)                       # bool per point (closed meshes)
    w = scene.winding_number(points)                 # generalized winding number per point (float64)
    ins = scene.inside(points, method="winding")     # any mesh (open, overlapping): winding >= 0.5
    sd = scene.signed_distance(points)               # closest distance, negative inside
    inst = scene.add_instance(geom, transform)       # a mesh placed again by a (3, 4) affine

Rays and points may have any leading shape, (N, 3), (H, W, 3) or one (3,), and the results take
it. Every query takes threads= (0: the scene's setting); the answers do not depend on it. Arrays
may come from anything exposing the buffer protocol, __array_interface__ or DLPack; float32
arrays are read in place. Work runs with the GIL released. help(arbor.Scene) documents each call;
the contract is ../shared/spec/python.md.
"""
import numpy as _np

from ._arbor import Scene, __version__, kernel_set, read_rays


def _records(fields, itemsize):
    """A record dtype of (name, format, offset) fields laid over arbor's records of `itemsize` bytes."""
    return _np.dtype({"names": [f[0] for f in fields], "formats": [f[1] for f in fields],
                      "offsets": [f[2] for f in fields], "itemsize": itemsize})


_HIT = [("t", "<f4", 0), ("geom", "<u4", 4), ("prim", "<u4", 8), ("u", "<f4", 12), ("v", "<f4", 16)]
_INST_HIT = _HIT[:3] + [("inst", "<u4", 20)] + _HIT[3:]
_POINT = [("distance", "<f4", 0), ("geom", "<u4", 4), ("prim", "<u4", 8), ("point", "3<f4", 12), ("u", "<f4", 24),
          ("v", "<f4", 28)]
_INST_POINT = _POINT[:3] + [("inst", "<u4", 32)] + _POINT[3:]

#: The record of a hit (intersect, intersect_all): a miss is t = inf, geom = prim = MISS, u = v = 0.
#: 24 bytes a record (4 of them unused: the inst field of a scene with instances).
hit_dtype = _records(_HIT, 24)
#: A hit with its triangle's unit geometric normal (normals=True); zeros for a miss.
hit_normal_dtype = _records(_HIT + [("normal", "3<f4", 24)], 36)
#: The record of a closest point: nothing within reach is distance = inf, geom = prim = MISS.
point_dtype = _records(_POINT, 36)
#: The records of a scene that holds instances (Scene.add_instance): the same and inst (uint32),
#: the instance that placed the mesh (MISS for a miss and for meshes placed without an instance).
hit_inst_dtype = _records(_INST_HIT, 24)
hit_inst_normal_dtype = _records(_INST_HIT + [("normal", "3<f4", 24)], 36)
point_inst_dtype = _records(_INST_POINT, 36)
#: geom and prim of a miss.
MISS = 0xFFFFFFFF

__all__ = ["Scene", "read_rays", "kernel_set", "hit_dtype", "hit_normal_dtype", "point_dtype", "hit_inst_dtype",
           "hit_inst_normal_dtype", "point_inst_dtype", "MISS", "__version__"]
