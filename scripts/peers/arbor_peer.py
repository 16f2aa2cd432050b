"""arbor through its Python module: the structure --accel auto picks, numpy arrays read in place."""
import time

import numpy as np

import arbor


class ArborPeer:
    name = "arbor"
    offers = {"closest", "any", "count", "closest_point", "inside"}

    def __init__(self, threads):
        self.threads = threads

    def build(self, verts, faces):
        t0 = time.perf_counter()
        self.scene = arbor.Scene(verts, faces)
        self.scene.build(accel="auto", threads=self.threads)
        return (time.perf_counter() - t0) * 1e3

    def describe(self):
        return f"arbor {arbor.__version__} ({self.scene.accel}, kernel set {arbor.kernel_set()})"

    def prepare_rays(self, o, d, tnear, tfar):
        return (np.ascontiguousarray(o), np.ascontiguousarray(d), tnear, tfar)

    def prepare_points(self, p):
        return np.ascontiguousarray(p)

    def closest(self, r):
        h = self.scene.intersect(*r)
        return h["t"]

    def any(self, r):
        return self.scene.occluded(*r)

    def count(self, r):
        return self.scene.intersect_all(*r, max_hits=0)[1]

    def closest_point(self, p):
        return self.scene.closest_point(p)["distance"]

    def inside(self, p):
        return self.scene.inside(p)
