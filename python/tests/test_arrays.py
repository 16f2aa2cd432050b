"""Arguments: dtypes, shapes and layouts that are read in place, converted, or refused with a
message naming the argument; the GIL is released while arbor works."""
import threading
import time
import tracemalloc

import numpy as np
import pytest

import arbor
from conftest import random_rays
from test_sources import sources


def test_conversions_give_the_same_answers(box_scene):
    o = np.array([[0.125, 0.25, -5], [0.375, -0.25, 5]], np.float32)  # exact in float16 too
    d = np.array([[0, 0, 1], [0, 0, -1]], np.float32)
    ref = box_scene.intersect(o, d)
    assert np.all(np.isfinite(ref["t"]))
    variants = [
        (o.astype(np.float64), d.astype(np.float64)),          # float64: converted
        (o.tolist(), d.tolist()),                               # lists
        (np.asfortranarray(o), np.asfortranarray(d)),           # column-major: copied
        (o.astype(">f4"), d.astype(">f4")),                     # big-endian: converted
        (np.array(o.T).T, d),                                   # a transposed view
        (o[::-1][::-1], d[::-1][::-1]),                         # reversed twice
        (np.hstack([o, o])[:, :3], np.hstack([d, d])[:, 3:]),   # rows with a stride
        (o.astype(np.float16), d.astype(np.int64)),             # other reals
    ]
    for vo, vd in variants:
        assert box_scene.intersect(vo, vd).tobytes() == ref.tobytes()
    # One origin (or one direction) for every ray.
    h = box_scene.intersect(o[:1], np.repeat(d[:1], 5, axis=0))
    assert h.shape == (5,) and np.all(h["t"] == ref["t"][0])
    h = box_scene.intersect(np.broadcast_to(o[0], (7, 3)), d[:1])
    assert h.shape == (7,) and np.all(h["t"] == ref["t"][0])
    # tnear / tfar: numbers, numpy scalars, 0-d arrays, per-ray arrays of any real dtype.
    for tn in (0, 0.0, np.float32(0), np.array(0.0), np.zeros(2), np.zeros(2, np.int8), [0.0, 0.0]):
        assert box_scene.intersect(o, d, tnear=tn).tobytes() == ref.tobytes()
    assert np.all(np.isinf(box_scene.intersect(o, d, tfar=np.array([1.0, 1.0]))["t"]))


@pytest.mark.parametrize("call", ["intersect", "occluded", "intersect_all"])
def test_ray_argument_errors_name_the_argument(box_scene, call):
    f = getattr(box_scene, call)
    o = np.zeros((4, 3), np.float32)
    d = np.ones((4, 3), np.float32)
    with pytest.raises(ValueError, match=r"origins: expected shape \(N, 3\) or \(\.\.\., 3\), got \(4, 2\)"):
        f(o[:, :2], d)
    with pytest.raises(ValueError, match=r"directions: expected shape \(N, 3\) or \(\.\.\., 3\), got \(12,\)"):
        f(o, d.ravel())
    with pytest.raises(ValueError, match="directions: expected 4 rows like origins"):
        f(o, d[:3])
    with pytest.raises(TypeError, match=r"origins: expected a float32 array of shape \(N, 3\) or \(\.\.\., 3\), got dtype bool"):
        f(o.astype(bool), d)
    with pytest.raises(TypeError, match="directions: .*got dtype <U1"):
        f(o, np.full((4, 3), "a"))
    with pytest.raises(TypeError, match="origins: .*got dtype object"):
        f([[1, 2, None]] * 4, d)
    with pytest.raises(ValueError, match=r"tnear: expected a number or shape \(4,\)"):
        f(o, d, tnear=np.zeros(3))
    with pytest.raises(TypeError, match="tfar: expected a number"):
        f(o, d, tfar="far")
    with pytest.raises(TypeError, match="tfar: expected a number"):
        f(o, d, tfar=None)


def test_point_argument_errors(box_scene):
    with pytest.raises(ValueError, match=r"points: expected shape \(N, 3\)"):
        box_scene.closest_point(np.zeros((2, 4), np.float32))
    with pytest.raises(TypeError, match="points: expected a float32 array"):
        box_scene.inside(np.zeros((2, 3), np.complex128))
    with pytest.raises(ValueError, match="max_distance: expected a number >= 0"):
        box_scene.closest_point(np.zeros((2, 3)), max_distance=-1)
    with pytest.raises(ValueError, match="max_distance"):
        box_scene.closest_point(np.zeros((2, 3)), max_distance=np.nan)
    with pytest.raises(ValueError, match="max_hits: expected an int >= 0, got -1"):
        box_scene.intersect_all(np.zeros((2, 3)), np.ones((2, 3)), max_hits=-1)
    assert box_scene.closest_point(np.zeros((0, 3), np.float32)).shape == (0,)
    assert box_scene.inside(np.zeros((0, 3))).shape == (0,)


def test_out_takes_the_results_in_place(spot):
    # out= is written and returned (the same object), with the answers of a call without it,
    # whatever it held before; reusing it allocates nothing the size of the results.
    s = arbor.Scene.load(spot)
    s.build("bvh-sah")
    o, d = random_rays(s, 5000, seed=9)
    for call, dtype in (("intersect", arbor.hit_dtype), ("occluded", np.bool_)):
        f = getattr(s, call)
        ref = f(o, d, tnear=0.01)
        out = np.frombuffer(np.random.default_rng(1).bytes(5000 * np.dtype(dtype).itemsize), dtype).copy()
        if dtype is np.bool_:
            out = ~ref  # every answer must change
        assert f(o, d, tnear=0.01, out=out) is out
        assert out.tobytes() == ref.tobytes(), call
        tracemalloc.start()
        f(o, d, 0.01, np.inf, out)
        peak = tracemalloc.get_traced_memory()[1]
        tracemalloc.stop()
        assert peak < 5000 * np.dtype(dtype).itemsize // 2, (call, peak)


@pytest.mark.parametrize("call", ["intersect", "occluded"])
def test_out_errors_name_the_argument(box_scene, call):
    f = getattr(box_scene, call)
    dtype = arbor.hit_dtype if call == "intersect" else np.dtype(bool)
    name = "arbor.hit_dtype" if call == "intersect" else "bool"
    o, d = np.zeros((4, 3), np.float32), np.ones((4, 3), np.float32)
    with pytest.raises(TypeError, match=f"out: expected a numpy array of dtype {name} and shape \\(4,\\), got dtype float32"):
        f(o, d, out=np.empty(4, np.float32))
    with pytest.raises(TypeError, match="out: expected a numpy array .*, got list"):
        f(o, d, out=[0] * 4)
    with pytest.raises(ValueError, match=r"out: expected .*, got shape \(5,\)"):
        f(o, d, out=np.empty(5, dtype))
    with pytest.raises(ValueError, match=r"out: expected .*, got shape \(4, 1\)"):
        f(o, d, out=np.empty((4, 1), dtype))
    with pytest.raises(ValueError, match=rf"out: expected a contiguous array .*got strides \({2 * dtype.itemsize},\)"):
        f(o, d, out=np.empty(8, dtype)[::2])
    if call == "intersect":  # 4-byte fields at an odd address (numpy calls its packed records aligned)
        with pytest.raises(ValueError, match=r"out: expected a contiguous array at a multiple of 4 bytes.* at byte 1 of 4"):
            f(o, d, out=np.empty(4 * dtype.itemsize + 1, np.uint8)[1:].view(dtype))
    ro = np.empty(4, dtype)
    ro.flags.writeable = False
    with pytest.raises(ValueError, match="out: the array is read-only"):
        f(o, d, out=ro)
    # The rays themselves as out: refused (the query reads them while it writes).
    records = np.zeros((4, 8), np.float32)
    records[:, 6] = 1.0
    with pytest.raises(ValueError, match="out: shares memory with an input"):
        f(records[:, :3], records[:, 4:7], out=records.view(np.uint8).ravel()[:4 * dtype.itemsize].view(dtype))


def test_float32_input_is_not_copied(box_scene):
    # numpy reports its allocations to tracemalloc: reading float32 rays in place allocates the
    # result only, also when they come through DLPack, __array_interface__ or the buffer protocol
    # (test_sources.py); float64 rays are converted (a float32 copy of each array).
    n = 200_000
    o32, d32 = random_rays(box_scene, n, seed=4)
    box_scene.intersect(o32[:10], d32[:10])  # built, warmed up
    result = n * arbor.hit_dtype.itemsize
    inputs = {"f32": (o32, d32), "f64": (o32.astype(np.float64), d32.astype(np.float64))}
    for name in ("dlpack", "array_interface", "memoryview"):
        inputs[name] = (sources(o32)[name], sources(d32)[name])
    peaks = {}
    for name, (o, d) in inputs.items():
        tracemalloc.start()
        box_scene.intersect(o, d)
        peaks[name] = tracemalloc.get_traced_memory()[1]
        tracemalloc.stop()
    for name in ("f32", "dlpack", "array_interface", "memoryview"):
        assert peaks[name] < result + 64 * 1024, (name, peaks)
    assert peaks["f64"] >= result + 2 * 12 * n, peaks


def test_the_gil_is_released_while_arbor_works(spot):
    # The main thread takes time stamps while another thread is inside Scene.intersect: with the
    # GIL held for the call, no stamp could fall within it.
    s = arbor.Scene.load(spot)
    s.build("bvh-sah")
    o, d = random_rays(s, 1_000_000, seed=6)
    window = []

    def work():
        t0 = time.perf_counter()
        s.intersect(o, d)
        window.extend([t0, time.perf_counter()])
    stamps = []
    t = threading.Thread(target=work)
    t.start()
    while t.is_alive():
        stamps.append(time.perf_counter())
        time.sleep(0.0005)
    t.join()
    inside = [x for x in stamps if window[0] < x < window[1]]
    assert len(inside) >= 5, (len(inside), window[1] - window[0])


def test_queries_from_several_python_threads_agree(spot):
    s = arbor.Scene.load(spot)
    s.build("lbvh", threads=2)
    o, d = random_rays(s, 20_000, seed=7)
    ref = s.intersect(o, d).tobytes()
    out = [None] * 4

    def work(i):
        out[i] = s.intersect(o, d).tobytes()
    threads = [threading.Thread(target=work, args=(i,)) for i in range(4)]
    for t in threads:
        t.start()
    s2 = threading.Thread(target=lambda: s.build("lbvh", threads=2))  # waits for the queries
    s2.start()
    for t in threads:
        t.join()
    s2.join()
    assert all(x == ref for x in out)
    assert s.intersect(o, d).tobytes() == ref
