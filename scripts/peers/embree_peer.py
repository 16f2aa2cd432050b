"""Embree 3 called directly (Debian libembree3), through ctypes: a triangle geometry with the same
float32 vertices and uint32 faces, the scene's default build, and the stream calls rtcIntersect1M
and rtcOccluded1M over RTCRayHit / RTCRay records (rtcore_ray.h), split into one contiguous block
per thread; once with Embree's default scene flags and once with RTC_SCENE_FLAG_ROBUST, its
watertight mode (ctypes drops the GIL during the call). Embree answers closest and any hit; counting
every crossing, closest points and inside need callbacks of the user's (filter and point-query
functions), which this benchmark does not write, so those rows name no Embree figure."""
import ctypes
import time
from concurrent.futures import ThreadPoolExecutor

import numpy as np

RAY = [("org", np.float32, 3), ("tnear", np.float32), ("dir", np.float32, 3), ("time", np.float32),
       ("tfar", np.float32), ("mask", np.uint32), ("id", np.uint32), ("flags", np.uint32)]
HIT = [("Ng", np.float32, 3), ("u", np.float32), ("v", np.float32), ("primID", np.uint32),
       ("geomID", np.uint32), ("instID", np.uint32)]
RAY_DTYPE = np.dtype(RAY)                              # struct RTCRay, 48 bytes
RAYHIT_DTYPE = np.dtype([("ray", RAY_DTYPE), ("hit", np.dtype(HIT))])  # struct RTCRayHit, 80 bytes
INVALID = 0xFFFFFFFF


class Context(ctypes.Structure):  # struct RTCIntersectContext with RTC_MAX_INSTANCE_LEVEL_COUNT 1
    _fields_ = [("flags", ctypes.c_int), ("filter", ctypes.c_void_p), ("instID", ctypes.c_uint * 1)]


class EmbreePeer:
    """robust: RTC_SCENE_FLAG_ROBUST (Open3D sets it; Embree's default leaves it off for speed)."""
    offers = {"closest", "any"}

    def __init__(self, threads, robust):
        self.name = "embree-robust" if robust else "embree"
        self.robust = robust
        assert RAY_DTYPE.itemsize == 48 and RAYHIT_DTYPE.itemsize == 80
        self.threads = threads
        self.lib = lib = ctypes.CDLL("libembree3.so.3")
        for fn in ("rtcNewDevice", "rtcNewScene", "rtcNewGeometry", "rtcSetNewGeometryBuffer"):
            getattr(lib, fn).restype = ctypes.c_void_p
        lib.rtcNewScene.argtypes = [ctypes.c_void_p]
        lib.rtcNewGeometry.argtypes = [ctypes.c_void_p, ctypes.c_int]
        lib.rtcSetNewGeometryBuffer.argtypes = [ctypes.c_void_p, ctypes.c_int, ctypes.c_uint, ctypes.c_int,
                                                ctypes.c_size_t, ctypes.c_size_t]
        for fn in ("rtcCommitGeometry", "rtcCommitScene", "rtcReleaseGeometry", "rtcReleaseScene"):
            getattr(lib, fn).argtypes = [ctypes.c_void_p]
        lib.rtcAttachGeometry.argtypes = [ctypes.c_void_p, ctypes.c_void_p]
        lib.rtcAttachGeometry.restype = ctypes.c_uint
        lib.rtcSetSceneFlags.argtypes = [ctypes.c_void_p, ctypes.c_int]
        stream = [ctypes.c_void_p, ctypes.POINTER(Context), ctypes.c_void_p, ctypes.c_uint, ctypes.c_size_t]
        lib.rtcIntersect1M.argtypes = stream
        lib.rtcOccluded1M.argtypes = stream
        self.device = lib.rtcNewDevice(f"threads={threads}".encode())
        self.scene = None
        self.pool = ThreadPoolExecutor(threads)

    def build(self, verts, faces):
        lib = self.lib
        if self.scene:
            lib.rtcReleaseScene(self.scene)
        t0 = time.perf_counter()
        self.scene = lib.rtcNewScene(self.device)
        if self.robust:
            lib.rtcSetSceneFlags(self.scene, 1 << 2)  # RTC_SCENE_FLAG_ROBUST
        geom = lib.rtcNewGeometry(self.device, 0)  # RTC_GEOMETRY_TYPE_TRIANGLE
        vb = lib.rtcSetNewGeometryBuffer(geom, 1, 0, 0x9003, 12, len(verts))  # VERTEX, FLOAT3
        ctypes.memmove(vb, np.ascontiguousarray(verts, np.float32).ctypes.data, verts.nbytes)
        ib = lib.rtcSetNewGeometryBuffer(geom, 0, 0, 0x5003, 12, len(faces))  # INDEX, UINT3
        ctypes.memmove(ib, np.ascontiguousarray(faces, np.uint32).ctypes.data, faces.nbytes)
        lib.rtcCommitGeometry(geom)
        lib.rtcAttachGeometry(self.scene, geom)
        lib.rtcReleaseGeometry(geom)
        lib.rtcCommitScene(self.scene)
        return (time.perf_counter() - t0) * 1e3

    def describe(self):
        flags = "RTC_SCENE_FLAG_ROBUST" if self.robust else "default scene flags"
        return f"Embree 3.13 (Debian libembree3, {flags}; rtcIntersect1M / rtcOccluded1M through ctypes)"

    def prepare_rays(self, o, d, tnear, tfar):
        n = len(o)
        rh = np.zeros(n, RAYHIT_DTYPE)
        rh["ray"]["org"], rh["ray"]["dir"] = o, d
        rh["ray"]["tnear"], rh["ray"]["tfar"] = tnear, tfar
        rh["ray"]["mask"] = INVALID
        rh["hit"]["geomID"] = INVALID
        rh["hit"]["instID"] = INVALID
        return rh

    def _stream(self, fn, records, stride):
        ctx = Context(0, None, (ctypes.c_uint * 1)(INVALID))
        n = len(records)
        step = -(-n // self.threads)
        base = records.ctypes.data

        def block(i):
            m = min(step, n - i)
            fn(self.scene, ctypes.byref(ctx), base + i * stride, m, stride)

        list(self.pool.map(block, range(0, n, step)))

    def closest(self, template):
        rh = template.copy()  # the call writes tfar and the hit: a fresh copy of the input each time
        self._stream(self.lib.rtcIntersect1M, rh, RAYHIT_DTYPE.itemsize)
        return np.where(rh["hit"]["geomID"] != INVALID, rh["ray"]["tfar"], np.float32(np.inf))

    def any(self, template):
        r = np.ascontiguousarray(template["ray"])
        self._stream(self.lib.rtcOccluded1M, r, RAY_DTYPE.itemsize)
        return r["tfar"] == -np.inf
