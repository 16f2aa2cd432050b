"""Every public name of arbor, used as a typed program uses it: checked by mypy --strict against the
stubs (test_typing.py) and run (test_typing.py), so the types it states are the ones returned."""
import pathlib
from typing import Any

import numpy as np
import numpy.typing as npt

import arbor


class DLPackRows:
    """A minimal DLPack producer (as a torch CPU tensor is one), backed by a numpy array."""

    def __init__(self, a: npt.NDArray[np.float32]) -> None:
        self._a = a

    def __dlpack__(self, stream: Any = None) -> Any:
        return self._a.__dlpack__()

    def __dlpack_device__(self) -> tuple[int, int]:
        return (1, 0)  # kDLCPU, device 0


def use_everything(model: pathlib.Path, rays_file: pathlib.Path) -> dict[str, object]:
    version: str = arbor.__version__
    kernels: str = arbor.kernel_set()
    miss: int = arbor.MISS
    dtypes: list[np.dtype[np.void]] = [arbor.hit_dtype, arbor.hit_normal_dtype, arbor.point_dtype]

    vertices = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], np.float32)
    faces = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]], np.int32)
    scene = arbor.Scene(vertices, faces)
    empty = arbor.Scene()
    geom: int = empty.add_mesh(vertices.astype(np.float64), faces)
    loaded = arbor.Scene.load(model)
    loaded.build("bvh-sah", threads=2, max_memory=0)
    scene.build()
    triangles: int = scene.triangles
    meshes: int = scene.meshes
    accel: str = scene.accel
    reason: str = scene.accel_reason
    bounds: npt.NDArray[np.float32] = scene.bounds

    origins = np.array([[0.2, 0.2, -1.0], [5.0, 5.0, -1.0]], np.float32)
    direction = np.array([0.0, 0.0, 1.0], np.float32)
    hits: npt.NDArray[np.void] = scene.intersect(origins, direction, 0.0, np.inf, threads=1)
    with_normals: npt.NDArray[np.void] = scene.intersect(DLPackRows(origins), direction, normals=True)
    scene.intersect(origins, direction, out=hits)
    buffer = memoryview(bytearray(origins.tobytes())).cast("f", (2, 3))  # the buffer protocol
    occ: npt.NDArray[np.bool_] = scene.occluded(buffer, direction, tnear=np.zeros(2), tfar=10.0)
    all_hits, counts = scene.intersect_all(origins, direction, max_hits=4, threads=0, normals=False)
    grid = np.zeros((3, 4, 3), np.float32) + origins[0]
    grid_hits: npt.NDArray[np.void] = scene.intersect(grid, direction)
    near: npt.NDArray[np.void] = scene.closest_point(np.array([0.1, 0.1, 0.1]), max_distance=2.0, threads=2)
    reach = np.array([0.5, np.inf], np.float32)
    nears: npt.NDArray[np.void] = scene.closest_point(origins, reach, out=np.empty(2, arbor.point_dtype))
    ins: npt.NDArray[np.bool_] = scene.inside(origins, out=np.empty(2, bool), threads=1)
    pts = np.array([[0.1, 0.1, 0.1], [5.0, 5.0, 5.0]], np.float32)
    winding: npt.NDArray[np.float64] = scene.winding_number(pts, threads=1, beta=4.0)
    ins_winding: npt.NDArray[np.bool_] = scene.inside(pts, "winding", exact=True)
    signed: npt.NDArray[np.float32] = scene.signed_distance(pts, method="winding", out=np.empty(2, np.float32))
    closed: bool = scene.closed
    o, d, tnear, tfar = arbor.read_rays(rays_file)
    file_hits: npt.NDArray[np.void] = loaded.intersect(o, d, tnear, tfar)
    return {
        "version": version, "kernels": kernels, "miss": miss, "dtypes": dtypes, "geom": geom,
        "triangles": triangles, "meshes": meshes, "accel": accel, "reason": reason, "bounds": bounds,
        "hits": hits, "with_normals": with_normals, "occ": occ, "all_hits": all_hits, "counts": counts,
        "grid_hits": grid_hits, "near": near, "nears": nears, "ins": ins, "file_hits": file_hits,
        "loaded": repr(loaded), "winding": winding, "ins_winding": ins_winding, "signed": signed,
        "closed": closed,
    }
