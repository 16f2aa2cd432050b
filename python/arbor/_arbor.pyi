"""Type stubs of arbor's extension module (python/module.cpp). The parameter names, their order,
kinds and defaults are those of the module: python/tests/test_stubs.py fails when they differ.
Shapes, dtypes and units are in the docstrings (help(arbor.Scene.intersect))."""
from math import inf
from os import PathLike
from typing import Any, Literal, Protocol, Union

import numpy as np
import numpy.typing as npt

class _SupportsDLPack(Protocol):
    def __dlpack__(self, *, stream: Any = ...) -> Any: ...
    def __dlpack_device__(self) -> tuple[int, int]: ...

class _SupportsArrayInterface(Protocol):
    @property
    def __array_interface__(self) -> dict[str, Any]: ...

# What an array argument may be: anything numpy takes, the buffer protocol, __array_interface__
# or DLPack (e.g. a torch CPU tensor).
_Array = Union[npt.ArrayLike, memoryview, _SupportsArrayInterface, _SupportsDLPack]
# tnear, tfar, max_distance: a number, or one per ray or point.
_PerItem = Union[float, _Array]
_Path = Union[str, PathLike[str]]
_Records = npt.NDArray[np.void]
_Bools = npt.NDArray[np.bool_]
_Counts = npt.NDArray[np.int32]
_Floats = npt.NDArray[np.float32]
_Doubles = npt.NDArray[np.float64]
# method= of inside and signed_distance.
_Method = Literal["parity", "winding"]

__version__: str

def kernel_set() -> str: ...
def read_rays(path: _Path) -> tuple[_Floats, _Floats, _Floats, _Floats]: ...

class Scene:
    def __init__(self, vertices: _Array | None = None, faces: _Array | None = None) -> None: ...
    @staticmethod
    def load(path: _Path) -> Scene: ...
    def add_mesh(self, vertices: _Array, faces: _Array) -> int: ...
    def build(self, accel: str = "auto", threads: int = 0, max_memory: int = 0, compact: bool = False) -> None: ...
    def add_instance(self, geom: int, transform: _Array) -> int: ...
    def set_transform(self, inst: int, transform: _Array) -> None: ...
    @property
    def instances(self) -> int: ...
    @property
    def triangles(self) -> int: ...
    @property
    def load_warnings(self) -> list[str]: ...
    @property
    def meshes(self) -> int: ...
    @property
    def accel(self) -> str: ...
    @property
    def accel_reason(self) -> str: ...
    @property
    def bounds(self) -> _Floats: ...
    def update_vertices(self, geom: int, vertices: _Array, *, mode: str = "auto", rays: float | None = None) -> None: ...
    @property
    def update_action(self) -> str: ...
    @property
    def update_reason(self) -> str: ...
    def intersect(
        self,
        origins: _Array,
        directions: _Array,
        tnear: _PerItem = 0.0,
        tfar: _PerItem = inf,
        out: _Records | None = None,
        *,
        threads: int = 0,
        normals: bool = False,
    ) -> _Records: ...
    def occluded(
        self,
        origins: _Array,
        directions: _Array,
        tnear: _PerItem = 0.0,
        tfar: _PerItem = inf,
        out: _Bools | None = None,
        *,
        threads: int = 0,
    ) -> _Bools: ...
    def intersect_all(
        self,
        origins: _Array,
        directions: _Array,
        tnear: _PerItem = 0.0,
        tfar: _PerItem = inf,
        max_hits: int = 16,
        *,
        out: tuple[_Records, _Counts] | None = None,
        threads: int = 0,
        normals: bool = False,
    ) -> tuple[_Records, _Counts]: ...
    def closest_point(
        self,
        points: _Array,
        max_distance: _PerItem = inf,
        *,
        out: _Records | None = None,
        threads: int = 0,
    ) -> _Records: ...
    def inside(
        self,
        points: _Array,
        method: _Method = "parity",
        *,
        out: _Bools | None = None,
        threads: int = 0,
        exact: bool = False,
        beta: float = 2.0,
    ) -> _Bools: ...
    def winding_number(
        self,
        points: _Array,
        *,
        out: _Doubles | None = None,
        threads: int = 0,
        exact: bool = False,
        beta: float = 2.0,
    ) -> _Doubles: ...
    def signed_distance(
        self,
        points: _Array,
        method: _Method = "parity",
        *,
        out: _Floats | None = None,
        threads: int = 0,
        exact: bool = False,
        beta: float = 2.0,
    ) -> _Floats: ...
    @property
    def closed(self) -> bool: ...
