"""fcpw (github.com/rohan-sawhney/fcpw, "fast closest point queries"), header-only C++ over
Eigen with optional SIMD through enoki, called through ctypes. Nothing of fcpw is kept in this
repository: build() compiles scripts/peers/fcpw_shim.cpp against the headers of a checkout given
with --fcpw (or ARBOR_FCPW) and Debian's Eigen (libeigen3-dev), with -O3 -march=native and the
flags fcpw's CMakeLists.txt adds for enoki; when enoki does not compile the shim is built scalar
and describe() says so. The scene is fcpw's surface-area BVH, vectorized (its README's choice).

Queries: closest hit is intersect (and, in a second column "fcpw robust", intersectRobust); any hit is intersect with checkForOcclusion; the crossing count
is intersect with recordAllHits (fcpw sorts the hits and drops duplicates at shared edges);
closest point is findClosestPoint; inside is contains (odd crossing counts along +x and +y).
fcpw's rays have no tnear and want unit directions: the shim starts each ray at o + tnear d along
d / |d| and maps t back (see fcpw_shim.cpp). The shim runs the given thread count itself, blocks
of queries handed out dynamically; ctypes drops the GIL during the call."""
import ctypes
import os
import subprocess
import tempfile
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
FLAGS = ["-std=c++17", "-O3", "-march=native", "-DNDEBUG", "-fPIC", "-shared", "-pthread",
         # what fcpw's CMakeLists.txt adds through enoki_set_compile_flags()
         "-fno-math-errno", "-ffp-contract=fast", "-fomit-frame-pointer", "-fno-stack-protector"]


def git_commit(path):
    try:
        out = subprocess.run(["git", "-C", path, "rev-parse", "--short=12", "HEAD"], capture_output=True, text=True)
        return out.stdout.strip() if out.returncode == 0 else None
    except OSError:
        return None


def compile_shim(fcpw_dir):
    """Path of the compiled shim and how it was built; raises RuntimeError with the compiler's
    last lines when even the scalar build fails."""
    include = os.path.join(fcpw_dir, "include")
    if not os.path.exists(os.path.join(include, "fcpw", "fcpw.h")):
        raise RuntimeError(f"--fcpw {fcpw_dir}: no include/fcpw/fcpw.h there")
    tmp = tempfile.mkdtemp(prefix="arbor-fcpw-")
    so = os.path.join(tmp, "fcpw_shim.so")
    base = ["g++"] + FLAGS + ["-I" + include, "-I/usr/include/eigen3", os.path.join(HERE, "fcpw_shim.cpp"), "-o", so]
    enoki = os.path.join(fcpw_dir, "deps", "enoki", "include")
    attempts = []
    if os.path.exists(os.path.join(enoki, "enoki", "array.h")):
        attempts.append(("enoki", base + ["-DFCPW_USE_ENOKI", "-I" + enoki]))
    attempts.append(("scalar", base))
    errors = []
    for kind, cmd in attempts:
        run = subprocess.run(cmd, capture_output=True, text=True)
        if run.returncode == 0:
            why = "" if kind == "enoki" or not errors else f" (enoki failed: {errors[-1]})"
            return so, why
        errors.append(run.stderr.strip().splitlines()[-1] if run.stderr.strip() else f"exit {run.returncode}")
    raise RuntimeError(f"fcpw shim did not compile: {errors[-1]}")


class FcpwPeer:
    """robust: closest hit only, through intersectRobust (fcpw's watertight ray-triangle test;
    its default intersect is Moller-Trumbore rejecting |det| <= FLT_EPSILON, an absolute bound)."""

    def __init__(self, threads, fcpw_dir, shim, robust=False):
        """shim: what compile_shim(fcpw_dir) returned (compiled once per run)."""
        self.name = "fcpw-robust" if robust else "fcpw"
        self.offers = {"closest"} if robust else {"closest", "any", "count", "closest_point", "inside"}
        self.robust = robust
        self.threads = threads
        self.dir = fcpw_dir
        so, self.fallback = shim
        self.lib = lib = ctypes.CDLL(so)
        ptr, i64, c_int = ctypes.c_void_p, ctypes.c_int64, ctypes.c_int
        lib.fcpw_config.restype = ctypes.c_char_p
        lib.fcpw_build.restype = ptr
        lib.fcpw_build.argtypes = [ptr, i64, ptr, i64, c_int]
        lib.fcpw_free.argtypes = [ptr]
        for fn in ("fcpw_closest", "fcpw_closest_robust", "fcpw_any", "fcpw_count"):
            getattr(lib, fn).argtypes = [ptr, ptr, ptr, ptr, ptr, i64, ptr, c_int]
        for fn in ("fcpw_closest_point", "fcpw_inside"):
            getattr(lib, fn).argtypes = [ptr, ptr, i64, ptr, c_int]
        self.scene = None

    def build(self, verts, faces):
        if self.scene:
            self.lib.fcpw_free(self.scene)
        v = np.ascontiguousarray(verts, np.float32)
        f = np.ascontiguousarray(faces, np.uint32)
        t0 = time.perf_counter()
        self.scene = self.lib.fcpw_build(v.ctypes.data, len(v), f.ctypes.data, len(f), 1)
        return (time.perf_counter() - t0) * 1e3

    def describe(self):
        commit = git_commit(self.dir)
        at = f" @{commit}" if commit else ""
        how = "intersectRobust" if self.robust else "intersect, findClosestPoint, contains"
        return (f"fcpw{at} ({self.lib.fcpw_config().decode()}{self.fallback}; surface-area BVH; {how}, "
                f"one query at a time on {self.threads} std::threads, through ctypes)")

    def prepare_rays(self, o, d, tnear, tfar):
        return tuple(np.ascontiguousarray(a, np.float32) for a in (o, d, tnear, tfar))

    def prepare_points(self, p):
        return np.ascontiguousarray(p, np.float32)

    def _rays(self, fn, r, dtype):
        out = np.empty(len(r[0]), dtype)
        fn(self.scene, *(a.ctypes.data for a in r), len(r[0]), out.ctypes.data, self.threads)
        return out

    def closest(self, r):
        return self._rays(self.lib.fcpw_closest_robust if self.robust else self.lib.fcpw_closest, r, np.float32)

    def any(self, r):
        return self._rays(self.lib.fcpw_any, r, np.uint8).view(bool)

    def count(self, r):
        return self._rays(self.lib.fcpw_count, r, np.int32)

    def closest_point(self, p):
        out = np.empty(len(p), np.float32)
        self.lib.fcpw_closest_point(self.scene, p.ctypes.data, len(p), out.ctypes.data, self.threads)
        return out

    def inside(self, p):
        out = np.empty(len(p), np.uint8)
        self.lib.fcpw_inside(self.scene, p.ctypes.data, len(p), out.ctypes.data, self.threads)
        return out.view(bool)
