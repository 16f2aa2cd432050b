"""Property tests (hypothesis): whatever arrays a caller passes, arbor answers or raises TypeError /
ValueError; it never crashes the interpreter, and its answers keep their invariants."""
import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

import arbor
from conftest import box_mesh

SETTINGS = settings(max_examples=80, deadline=None, database=None, suppress_health_check=[HealthCheck.function_scoped_fixture])

floats = st.floats(allow_nan=True, allow_infinity=True, width=32)
dtypes = st.sampled_from([np.float32, np.float64, np.float16, np.int32, np.uint8, np.bool_, np.complex64, ">f4"])
shapes = st.one_of(st.tuples(st.integers(0, 40), st.just(3)), hnp.array_shapes(min_dims=0, max_dims=3, max_side=5))


def arrays(dtype=dtypes, shape=shapes):
    """Arrays of any of those dtypes and shapes; float elements include NaN, +-inf and extremes."""
    return dtype.flatmap(lambda t: shape.flatmap(lambda s: hnp.arrays(t, s)))


_scene = None


def scene():
    global _scene
    if _scene is None:
        v, f = box_mesh()
        _scene = arbor.Scene(v, f)
        _scene.add_mesh(v * 3 + 1, f)
        _scene.build("bvh-sah", threads=2)
    return _scene


def call_or_reject(fn, *args, **kw):
    try:
        return fn(*args, **kw)
    except (TypeError, ValueError):
        return None


@SETTINGS
@given(o=arrays(), d=arrays(), tn=st.one_of(floats, arrays()), tf=st.one_of(floats, arrays()),
       strided=st.booleans(), max_hits=st.integers(-2, 5))
def test_rays_never_crash(o, d, tn, tf, strided, max_hits):
    s = scene()
    if strided and o.ndim == 2:
        o = np.repeat(o, 2, axis=0)[::2]
    h = call_or_reject(s.intersect, o, d, tn, tf)
    if h is not None:
        assert h.dtype == arbor.hit_dtype
        miss = np.isinf(h["t"])
        assert np.all((h["prim"] == arbor.MISS) == miss) and np.all(h["u"][miss] == 0)
        assert np.all((h["geom"] < 2) | miss)
    occ = call_or_reject(s.occluded, o, d, tn, tf)
    if occ is not None and h is not None:
        assert np.array_equal(occ, ~np.isinf(h["t"]))
    res = call_or_reject(s.intersect_all, o, d, tn, tf, max_hits=max_hits)
    if res is not None:
        hits, counts = res
        assert hits.shape == (len(counts), max_hits) and np.all(counts >= 0) and np.all(counts <= 24)
        if h is not None:
            assert np.array_equal(counts > 0, ~np.isinf(h["t"]))


@SETTINGS
@given(n=st.integers(0, 12), rows=st.one_of(st.none(), st.integers(0, 12)), kind=st.sampled_from(["hits", "bool", "other"]),
       other=dtypes, two_d=st.booleans(), step=st.sampled_from([1, 1, 2]), offset=st.sampled_from([0, 0, 1, 4]),
       readonly=st.booleans(), alias=st.booleans())
def test_out_never_crashes(n, rows, kind, other, two_d, step, offset, readonly, alias):
    # out= of any dtype, shape, stride, byte offset, writeability, or in the rays' own memory: the
    # answers of a call without out=, or TypeError / ValueError.
    s = scene()
    rays = np.zeros((n, 8), np.float32)
    rays[:, 0:3] = np.linspace(-4, 4, 3 * n, dtype=np.float32).reshape(n, 3)
    rays[:, 6] = 1.0
    o, d = rays[:, 0:3], rays[:, 4:7]
    rows = n if rows is None else rows
    for call in ("intersect", "occluded"):
        t = {"hits": arbor.hit_dtype, "bool": np.dtype(bool), "other": np.dtype(other)}[kind]
        buf = rays.view(np.uint8).ravel() if alias else np.zeros(rows * step * t.itemsize + offset + 8, np.uint8)
        fit = max(0, (len(buf) - offset) // (step * t.itemsize))
        k = min(rows, fit)
        out = np.ndarray((k, 1) if two_d else (k,), t, buffer=buf, offset=offset if k else 0,
                         strides=(step * t.itemsize, t.itemsize) if two_d else (step * t.itemsize,))
        out.flags.writeable = not readonly
        ref = getattr(s, call)(o, d)
        res = call_or_reject(getattr(s, call), o, d, out=out)
        if res is not None:
            assert res is out and out.tobytes() == ref.tobytes()
            assert t == ref.dtype and out.shape == (n,) and not readonly and not (alias and n)


@SETTINGS
@given(p=arrays(), reach=st.one_of(floats, st.integers(-3, 3)))
def test_points_never_crash(p, reach):
    s = scene()
    res = call_or_reject(s.closest_point, p, reach)
    if res is not None:
        ok = np.isfinite(res["distance"])
        assert np.all(res["distance"][ok] <= reach) and np.all(res["prim"][~ok] == arbor.MISS)
    ins = call_or_reject(s.inside, p)
    if ins is not None:
        assert ins.dtype == np.bool_


@SETTINGS
@given(v=arrays(), f=arrays(dtype=st.sampled_from([np.int64, np.int8, np.uint32, np.float32, np.bool_])))
def test_meshes_never_crash(v, f):
    s = arbor.Scene()
    if call_or_reject(s.add_mesh, v, f) is not None:
        s.build("bvh-sah")
        n = len(v) if v.ndim == 2 else 0
        h = s.intersect(np.zeros((4, 3), np.float32), np.ones((4, 3), np.float32))
        assert h.shape == (4,) and s.triangles == (len(f) if f.size else 0) and n >= 0
