"""Open3D's RaycastingScene (Debian python3-open3d 0.16), with its nthreads argument.

Debian's Embree is built with ray masks (EMBREE_RAY_MASK=ON) and Open3D never sets a ray's mask,
so every ray misses: Open3D's own wheels bundle an Embree built without ray masks. bench_peers.py
therefore runs with mask_shim.c preloaded, which sets each ray's mask to all ones on its way into
rtcIntersect1M and rtcOccluded1M (the two calls Open3D makes): Open3D then behaves as its wheels do.
check_mask() proves the shim took: one ray at the mesh must hit."""
import time

import numpy as np

import open3d as o3d


class Open3dPeer:
    name = "open3d"
    offers = {"closest", "any", "count", "closest_point", "inside"}

    def __init__(self, threads):
        self.threads = threads

    def build(self, verts, faces):
        t0 = time.perf_counter()
        self.scene = o3d.t.geometry.RaycastingScene()
        self.scene.add_triangles(o3d.core.Tensor(verts), o3d.core.Tensor(faces))
        # Embree builds lazily on the first query: one ray makes the build part of construction.
        self.scene.cast_rays(o3d.core.Tensor(np.zeros((1, 6), np.float32)), nthreads=self.threads)
        return (time.perf_counter() - t0) * 1e3

    def describe(self):
        return f"Open3D {o3d.__version__} RaycastingScene"

    def check_mask(self, verts):
        centre = (verts.max(axis=0) + verts.min(axis=0)) / 2
        far = centre + np.array([0, 0, 10 * float(np.ptp(verts))], np.float32)
        ray = np.concatenate([far, centre - far]).astype(np.float32)[None]
        t = self.scene.cast_rays(o3d.core.Tensor(ray))["t_hit"].numpy()
        return bool(np.isfinite(t[0]))

    def prepare_rays(self, o, d, tnear, tfar):
        return o3d.core.Tensor(np.ascontiguousarray(np.concatenate([o, d], axis=1), np.float32)), tnear, tfar

    def prepare_points(self, p):
        return o3d.core.Tensor(np.ascontiguousarray(p, np.float32))

    def closest(self, r):
        return self.scene.cast_rays(r[0], nthreads=self.threads)["t_hit"].numpy()

    def any(self, r):
        tnear, tfar = r[1], r[2]
        # One tnear and tfar for all rays: the rays come scaled so that all run over [0, 1].
        return self.scene.test_occlusions(r[0], tnear=float(np.max(tnear)), tfar=float(np.max(tfar)),
                                          nthreads=self.threads).numpy().astype(bool)

    def count(self, r):
        return self.scene.count_intersections(r[0], nthreads=self.threads).numpy()

    def closest_point(self, p):
        return self.scene.compute_distance(p, nthreads=self.threads).numpy()

    def inside(self, p):
        return self.scene.compute_occupancy(p, nthreads=self.threads).numpy() > 0.5
