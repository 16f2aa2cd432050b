"""Arrays from anywhere: DLPack producers (as a torch CPU tensor is one), objects exposing only
__array_interface__, and the buffer protocol give the answers of numpy arrays, read in place."""
import array
import tracemalloc

import numpy as np
import pytest

import arbor
from conftest import random_rays


class DLPackOnly:
    """Exposes a numpy array through DLPack only (no __array__, no buffer, no __array_interface__)."""

    def __init__(self, a):
        self._a = a

    def __dlpack__(self, stream=None):
        return self._a.__dlpack__()

    def __dlpack_device__(self):
        return self._a.__dlpack_device__()


class InterfaceOnly:
    """Exposes a numpy array through __array_interface__ only."""

    def __init__(self, a):
        self._a = a
        self.__array_interface__ = a.__array_interface__


class GpuTensor:
    """A DLPack producer on a device numpy cannot read (CUDA)."""

    def __dlpack__(self, stream=None):
        raise BufferError("on the GPU")

    def __dlpack_device__(self):
        return (2, 0)


def sources(a):
    return {"dlpack": DLPackOnly(a), "array_interface": InterfaceOnly(a), "memoryview": memoryview(a)}


def test_torch_when_importable(box_scene):
    torch = pytest.importorskip("torch")  # absent here; DLPackOnly stands in for it below
    o = torch.tensor([[0.1, 0.2, -5.0]])
    d = torch.tensor([[0.0, 0.0, 1.0]])
    assert box_scene.intersect(o, d)["t"][0] == pytest.approx(4.0)


def test_every_source_gives_the_answers_of_numpy(spot):
    s = arbor.Scene.load(spot)
    s.build("bvh-sah")
    o, d = random_rays(s, 2000, seed=21)
    tn = np.full(2000, 0.01, np.float32)
    pts = o * np.float32(0.3)
    ref = s.intersect(o, d, tn)
    assert np.count_nonzero(ref["prim"] != arbor.MISS) > 200
    for name in ("dlpack", "array_interface", "memoryview"):
        so, sd, stn, sp = sources(o)[name], sources(d)[name], sources(tn)[name], sources(pts)[name]
        assert s.intersect(so, sd, stn).tobytes() == ref.tobytes(), name
        assert np.array_equal(s.occluded(so, sd, tfar=stn), s.occluded(o, d, tfar=tn)), name
        assert s.closest_point(sp, max_distance=sources(np.full(2000, 0.2, np.float32))[name]).tobytes() == \
            s.closest_point(pts, max_distance=np.full(2000, 0.2, np.float32)).tobytes(), name
        assert np.array_equal(s.inside(sp), s.inside(pts)), name
    # Meshes too, and a flat buffer of another layout (array.array) where numpy takes it.
    v, f = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], np.float32), np.array([[0, 1, 2]], np.int64)
    for name in ("dlpack", "array_interface", "memoryview"):
        t = arbor.Scene(sources(v)[name], sources(f)[name])
        assert t.triangles == 1 and t.intersect([0.2, 0.2, 1.0], [0, 0, -1.0])["t"] == pytest.approx(1.0), name
    assert arbor.Scene(v, f).closest_point(array.array("f", [0.2, 0.2, 1.0]))["distance"] == pytest.approx(1.0)


@pytest.mark.parametrize("name", ["dlpack", "array_interface", "memoryview"])
def test_points_from_every_source_are_read_in_place(box_scene, name):
    # As test_arrays.py's test_float32_input_is_not_copied for rays: numpy reports its allocations
    # to tracemalloc, and points read in place allocate only the (N,) bool result.
    n = 200_000
    p = random_rays(box_scene, n, seed=4)[0] * np.float32(0.01)
    box_scene.inside(p[:10])  # built, warmed up
    src = sources(p)[name]
    tracemalloc.start()
    ins = box_scene.inside(src)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    assert ins.all() and peak < n + 64 * 1024, peak


def test_source_errors_name_the_argument(box_scene):
    with pytest.raises(TypeError, match=r"origins: expected .*, got GpuTensor that numpy cannot make an array of "
                                        r"\(numpy.from_dlpack: .*\)"):
        box_scene.intersect(GpuTensor(), np.ones((1, 3)))
    with pytest.raises(TypeError, match="points: expected a float32 array .* got dtype"):
        box_scene.inside(InterfaceOnly(np.zeros((2, 3), np.complex64)))
    with pytest.raises(ValueError, match=r"directions: expected shape \(N, 3\) or \(\.\.\., 3\), got \(2, 4\)"):
        box_scene.occluded(np.zeros((2, 3)), DLPackOnly(np.zeros((2, 4), np.float32)))
