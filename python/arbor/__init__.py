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

Rays and points may have any leading shape, (N, 3), (H, W, 3) or one (3,), and the results take
it. Every query takes threads= (0: the scene's setting); the answers do not depend on it. Arrays
may come from anything exposing the buffer protocol, __array_interface__ or DLPack; float32
arrays are read in place. Work runs with the GIL released. help(arbor.Scene) documents each call;
the contract is ../shared/spec/python.md.
"""
import numpy as _np

from ._arbor import Scene, __version__, kernel_set, read_rays

#: The record of a hit (intersect, intersect_all): a miss is t = inf, geom = prim = MISS, u = v = 0.
hit_dtype = _np.dtype([("t", "<f4"), ("geom", "<u4"), ("prim", "<u4"), ("u", "<f4"), ("v", "<f4")])
#: A hit with its triangle's unit geometric normal (normals=True); zeros for a miss.
hit_normal_dtype = _np.dtype([("t", "<f4"), ("geom", "<u4"), ("prim", "<u4"), ("u", "<f4"), ("v", "<f4"),
                              ("normal", "<f4", (3,))])
#: The record of a closest point: nothing within reach is distance = inf, geom = prim = MISS.
point_dtype = _np.dtype([("distance", "<f4"), ("geom", "<u4"), ("prim", "<u4"), ("point", "<f4", (3,)),
                         ("u", "<f4"), ("v", "<f4")])
#: geom and prim of a miss.
MISS = 0xFFFFFFFF

__all__ = ["Scene", "read_rays", "kernel_set", "hit_dtype", "hit_normal_dtype", "point_dtype", "MISS", "__version__"]
