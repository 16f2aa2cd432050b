"""Scenes: construction, files, meshes with geometry ids, building, properties and errors."""
import pathlib
import re

import numpy as np
import pytest

import arbor
from conftest import box_mesh


def test_import_version_and_kernels():
    assert isinstance(arbor.__version__, str) and arbor.__version__.count(".") == 2
    assert arbor.kernel_set() in ("avx512", "avx2", "sse4")


def test_load_builds_and_reports(spot):
    s = arbor.Scene.load(spot)
    assert s.triangles == 5856 and s.meshes == 1 and s.accel == ""
    s.build("bvh-sah", threads=1)
    assert s.accel == "bvh-sah"
    s.build()  # auto: a real structure and its reason
    assert s.accel in ("brute", "bvh-median", "bvh-sah", "lbvh", "kdtree") and s.accel_reason
    assert "5856 triangles" in repr(s)
    lo, hi = s.bounds
    assert np.all(lo < hi)


def test_load_reads_every_format_arbor_info_reads(tmp_path):
    """A PLY file (not only OBJ) loads with the file's own triangle numbering."""
    v, f = box_mesh()
    ply = tmp_path / "box.ply"
    head = f"ply\nformat ascii 1.0\nelement vertex {len(v)}\nproperty float x\nproperty float y\nproperty float z\n" \
           f"element face {len(f)}\nproperty list uchar int vertex_indices\nend_header\n"
    ply.write_text(head + "".join(f"{a} {b} {c}\n" for a, b, c in v) + "".join(f"3 {a} {b} {c}\n" for a, b, c in f))
    s, ref = arbor.Scene.load(ply), arbor.Scene(v, f)
    assert s.triangles == 12
    o = np.array([[0.1, 0.2, -5], [0.3, -0.4, 5], [5, 0.1, 0.2]], np.float32)
    d = np.array([[0, 0, 1], [0, 0, -1], [-1, 0, 0]], np.float32)
    assert s.intersect(o, d).tobytes() == ref.intersect(o, d).tobytes()


def test_load_reads_ply_triangle_strips():
    """The strips regression file (tests/data/meshes): 8 triangles, not one; each facing -z."""
    path = pathlib.Path(__file__).resolve().parents[2] / "tests" / "data" / "meshes" / "strips-le.ply"
    s = arbor.Scene.load(path)
    assert s.triangles == 8
    # Rays from +z down onto the ribbons hit; the triangle numbers are the strips' order.
    o = np.array([[0.25, 0.25, 1], [4.75, 0.75, 1], [7.75, 0.75, 1]], np.float32)
    h = s.intersect(o, np.array([[0, 0, -1]], np.float32))
    assert list(h["prim"]) == [0, 5, 7]
    assert s.load_warnings == []


def test_load_warns_about_data_it_reads_past(tmp_path):
    """A PLY edge element is no surface: skipped, and said in load_warnings."""
    ply = tmp_path / "edges.ply"
    ply.write_text("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                   "element face 1\nproperty list uchar int vertex_indices\nelement edge 1\nproperty int vertex1\n"
                   "property int vertex2\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n0 1\n")
    s = arbor.Scene.load(ply)
    assert s.triangles == 1
    assert s.load_warnings == [f"{ply}: PLY data not read (no surfaces): element 'edge' (1 record)"]


def test_meshes_get_geometry_ids_and_numbering():
    v, f = box_mesh()
    s = arbor.Scene(v, f)
    assert s.add_mesh(v + np.float32(5), f) == 1
    assert s.add_mesh((v * 0.5 + 10).astype(np.float64), f.astype(np.uint16)) == 2
    assert s.triangles == 36 and s.meshes == 3
    o = np.array([[0, 0, -5], [5, 5, -5], [10, 10, -5], [20, 20, -5]], np.float32)
    d = np.array([0, 0, 1], np.float32)[None, :]  # one direction for all rays
    h = s.intersect(o, d)
    assert list(h["geom"]) == [0, 1, 2, arbor.MISS]
    assert np.all(h["prim"][:3] < 12) and h["prim"][3] == arbor.MISS
    np.testing.assert_allclose(h["t"][:3], [4.0, 9.0, 14.5], rtol=1e-6)


def test_empty_scene_and_lazy_build():
    s = arbor.Scene()
    assert s.triangles == 0
    h = s.intersect(np.zeros((3, 3), np.float32), np.ones((3, 3), np.float32))
    assert np.all(np.isinf(h["t"])) and np.all(h["prim"] == arbor.MISS)
    v, f = box_mesh()
    s.add_mesh(v, f)  # the structure is built again on the next query
    assert s.intersect([[0, 0, -5]], [[0, 0, 1]])["t"][0] == pytest.approx(4.0)


def test_file_errors(tmp_path):
    with pytest.raises(OSError, match="cannot open"):
        arbor.Scene.load(tmp_path / "missing.obj")
    with pytest.raises(OSError, match="is a directory"):
        arbor.Scene.load(tmp_path)
    bad = tmp_path / "bad.obj"
    bad.write_text("v 0 0 0\nv 1 0 0\nv nan 1 0\nf 1 2 3\n")
    with pytest.raises(ValueError, match="bad.obj:3"):
        arbor.Scene.load(bad)
    with pytest.raises(TypeError, match="path"):
        arbor.Scene.load(3.5)
    rays = tmp_path / "x.rays"
    rays.write_bytes(b"RAYS\x01\x00\x00\x00" + (5).to_bytes(8, "little"))
    with pytest.raises(ValueError, match="x.rays"):
        arbor.read_rays(rays)


def test_build_errors(box_scene):
    with pytest.raises(ValueError, match="unknown structure 'octree'"):
        box_scene.build("octree")
    with pytest.raises(ValueError, match="threads"):
        box_scene.build("bvh-sah", threads=-1)
    with pytest.raises(MemoryError, match="max_memory"):
        box_scene.build("bvh-sah", max_memory=100)
    with pytest.raises(ValueError, match="max_memory"):
        box_scene.build("bvh-sah", max_memory=-5)
    box_scene.build("lbvh")  # still usable
    assert box_scene.accel == "lbvh"


def test_mesh_errors():
    v, f = box_mesh()
    s = arbor.Scene()
    with pytest.raises(ValueError, match="faces: row 1 holds vertex index 8"):
        s.add_mesh(v, np.array([[0, 1, 2], [0, 1, 8]]))
    with pytest.raises(ValueError, match="faces: row 0 holds vertex index -1"):
        s.add_mesh(v, np.array([[0, 1, -1]]))
    with pytest.raises(TypeError, match="faces: expected an integer array"):
        s.add_mesh(v, f.astype(np.float32))
    with pytest.raises(ValueError, match=r"vertices: expected shape \(N, 3\), got \(8, 2\)"):
        s.add_mesh(v[:, :2], f)
    with pytest.raises(TypeError, match="vertices: expected a float32 array"):
        s.add_mesh(v.astype(np.complex64), f)
    with pytest.raises(TypeError, match="vertices and faces"):
        arbor.Scene(v)
    assert s.triangles == 0  # nothing was added by the failed calls
    assert s.add_mesh(v, []) == 0  # no faces is fine


def test_compact_build_answers_as_the_default(spot):
    """build(compact=True): the BVHs' compact mode; the same closest hits, bit for bit, and the same occlusion."""
    s, ref = arbor.Scene.load(spot), arbor.Scene.load(spot)
    s.build("bvh-sah", compact=True)
    ref.build("bvh-sah")
    rng = np.random.default_rng(5)
    lo, hi = ref.bounds
    o = (lo + (hi - lo) * rng.uniform(-0.5, 1.5, (4000, 3))).astype(np.float32)
    d = rng.normal(size=(4000, 3)).astype(np.float32)
    assert s.intersect(o, d).tobytes() == ref.intersect(o, d).tobytes()
    assert np.array_equal(s.occluded(o, d), ref.occluded(o, d))
    with pytest.raises(TypeError, match="compact"):
        s.build("bvh-sah", compact="yes")


def test_max_memory_falls_back_to_compact_mode(spot):
    """Under a limit the default layout does not fit but compact mode does, the build is compact,
    says why in accel_reason, and answers as compact=True does; below that it is a MemoryError."""
    s = arbor.Scene.load(spot)

    def builds(limit):
        try:
            s.build("bvh-sah", max_memory=limit)
            return True
        except MemoryError:
            return False

    lo, hi = 1, 1 << 30  # lo refused, hi builds
    assert builds(hi) and "compact mode" not in s.accel_reason
    assert not builds(lo)
    while hi - lo > 1:
        mid = (lo + hi) // 2
        lo, hi = (lo, mid) if builds(mid) else (mid, hi)
    assert builds(hi)  # the least limit that builds: only compact mode fits there
    assert re.search(r"compact mode: bvh-sah: its (4|8|16)-wide SIMD layout needs", s.accel_reason), s.accel_reason
    rng = np.random.default_rng(3)
    lo_box, hi_box = s.bounds
    o = rng.uniform(lo_box, hi_box, (2000, 3)).astype(np.float32)
    d = rng.normal(size=(2000, 3)).astype(np.float32)
    got = s.intersect(o, d)
    c = arbor.Scene.load(spot)
    c.build("bvh-sah", compact=True)
    assert got.tobytes() == c.intersect(o, d).tobytes()
    with pytest.raises(MemoryError, match="max_memory"):
        s.build("bvh-sah", max_memory=lo)
