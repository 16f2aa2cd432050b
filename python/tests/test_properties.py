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
        assert hits.shape == counts.shape + (max_hits,) and np.all(counts >= 0) and np.all(counts <= 24)
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
        assert np.all(res["distance"][ok] <= reach)
        # An infinite distance is a miss, or a triangle found at a distance past float32's range
        # (a point beyond ~1e38: the distance, exact in double, rounds to inf).
        found = ~ok & (res["prim"] != arbor.MISS)
        if np.any(found):
            f = found.ravel()
            q = np.asarray(p, np.float64).reshape(-1, 3)[f]
            far = np.linalg.norm(q - res["point"].reshape(-1, 3)[f].astype(np.float64), axis=1)
            assert np.all(far >= 0.999 * np.finfo(np.float32).max)
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


threads = st.one_of(st.sampled_from([0, 1, 2, 3, 1000]), st.integers(-2, 4), st.sampled_from(["2", 1.5, None, True]))
lead_shapes = hnp.array_shapes(min_dims=0, max_dims=3, min_side=0, max_side=4)


@SETTINGS
@given(lead=lead_shapes, one_origin=st.booleans(), t=threads, normals=st.one_of(st.booleans(), st.just(1)),
       seed=st.integers(0, 2**16), max_hits=st.integers(0, 3))
def test_shapes_threads_and_normals_keep_the_answers(lead, one_origin, t, normals, seed, max_hits):
    # Rays of any leading shape (one origin for all, or one each), any threads= and normals=: the
    # answers of the same rays as a flat (N, 3) batch on one thread, in the rays' shape, or
    # TypeError / ValueError for a threads= or normals= that is not an int >= 0 or a bool.
    s = scene()
    rng = np.random.default_rng(seed)
    d = rng.normal(size=lead + (3,)).astype(np.float32)
    o = (rng.normal(size=(3,) if one_origin else lead + (3,)) * 6).astype(np.float32)
    valid = isinstance(t, int) and not isinstance(t, bool) and t >= 0 and isinstance(normals, bool)
    h = call_or_reject(s.intersect, o, d, threads=t, normals=normals)
    assert (h is not None) == valid
    if not valid:
        return
    flat_o = np.broadcast_to(o, lead + (3,)).reshape(-1, 3)
    ref = s.intersect(flat_o, d.reshape(-1, 3), threads=1, normals=normals)
    assert h.shape == lead and h.tobytes() == ref.tobytes()
    if normals:
        hit = ref["prim"] != arbor.MISS
        assert np.allclose(np.linalg.norm(ref["normal"][hit], axis=1), 1, atol=1e-6) and np.all(ref["normal"][~hit] == 0)
    occ = s.occluded(o, d, threads=t)
    assert occ.shape == lead and np.array_equal(occ.reshape(-1), ref["prim"] != arbor.MISS)
    rows, counts = s.intersect_all(o, d, max_hits=max_hits, threads=t, normals=normals)
    ref_rows, ref_counts = s.intersect_all(flat_o, d.reshape(-1, 3), max_hits=max_hits, threads=1, normals=normals)
    assert rows.shape == lead + (max_hits,) and counts.shape == lead
    assert rows.tobytes() == ref_rows.tobytes() and counts.tobytes() == ref_counts.tobytes()
    near = s.closest_point(o * np.float32(0.5), max_distance=np.float32(2.0), threads=t)
    assert near.shape == o.shape[:-1]
    assert near.tobytes() == s.closest_point((o * np.float32(0.5)).reshape(-1, 3), 2.0, threads=1).tobytes()
    ins = s.inside(d, threads=t)
    assert ins.shape == lead and np.array_equal(ins.reshape(-1), s.inside(d.reshape(-1, 3), threads=1))


@SETTINGS
@given(p=arrays(), reach=st.one_of(floats, arrays(dtype=st.sampled_from([np.float32, np.float64, np.int8]))),
       out_kind=st.sampled_from(["none", "right", "wrong_shape", "wrong_dtype"]))
def test_max_distance_arrays_and_out_never_crash(p, reach, out_kind):
    # max_distance of any shape and value, and out= right or wrong, on points of any shape: an
    # answer within each point's reach, or TypeError / ValueError.
    s = scene()
    lead = p.shape[:-1] if p.ndim >= 1 and p.shape[-1] == 3 else (2,)
    out = {"none": None, "right": np.empty(lead, arbor.point_dtype), "wrong_shape": np.empty(lead + (1,), arbor.point_dtype),
           "wrong_dtype": np.empty(lead, np.float32)}[out_kind]
    res = call_or_reject(s.closest_point, p, reach, out=out)
    if res is not None:
        assert out_kind in ("none", "right") and res.shape == lead
        if out is not None:
            assert res is out
        ok = np.isfinite(res["distance"])
        with np.errstate(over="ignore"):  # a float64 reach beyond float32 is inf, as arbor takes it
            limit = np.broadcast_to(np.asarray(reach, np.float32), res.shape)
        assert np.all(res["distance"][ok] <= limit[ok]) and np.all(res["prim"][~ok] == arbor.MISS)
