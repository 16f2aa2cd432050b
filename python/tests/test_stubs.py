"""The type stubs agree with the module (names, parameters, defaults), the comparison catches a
stub that does not, and every public function has a docstring naming each of its parameters."""
import ast
import inspect
import pathlib
import pydoc

import pytest

import arbor
import arbor._arbor
from stub_check import differences, signature_of

PACKAGE = pathlib.Path(arbor.__file__).resolve().parent
SOURCE = pathlib.Path(__file__).resolve().parents[1] / "arbor"


def test_the_build_has_the_stubs_and_py_typed_of_the_source_tree():
    for name in ("__init__.pyi", "_arbor.pyi", "py.typed"):
        assert (PACKAGE / name).read_bytes() == (SOURCE / name).read_bytes(), name


def test_the_extension_stub_agrees_with_the_extension():
    problems, _ = differences((SOURCE / "_arbor.pyi").read_text(), arbor._arbor)
    assert problems == []


def test_the_package_stub_agrees_with_the_package():
    source = (SOURCE / "__init__.pyi").read_text()
    problems, imports = differences(source, arbor)
    assert problems == []
    assert imports and all(target.startswith("_arbor.") for target in imports.values())
    stub_all = next(n.value for n in ast.parse(source).body
                    if isinstance(n, ast.Assign) and getattr(n.targets[0], "id", None) == "__all__")
    assert sorted(ast.literal_eval(stub_all)) == sorted(arbor.__all__)


def _plant(source, old, new):
    assert source.count(old) == 1, old
    return source.replace(old, new)


@pytest.mark.parametrize("old, new, expect", [
    ("max_hits: int = 16", "max_hit: int = 16", "Scene.intersect_all: parameters differ"),
    ("tfar: _PerItem = inf,\n        out: _Records | None = None,\n        *,\n        threads: int = 0,\n        normals",
     "tfar: _PerItem = 1.0,\n        out: _Records | None = None,\n        *,\n        threads: int = 0,\n        normals",
     "Scene.intersect: parameters differ"),
    ("    def inside(\n", "    def inside_out(\n", "Scene.inside: in the module, not in the stub"),
    ("        method: _Method = \"parity\",\n        *,\n        out: _Bools | None = None,",
     "        method: _Method = \"winding\",\n        *,\n        out: _Bools | None = None,",
     "Scene.inside: parameters differ"),
    ("def kernel_set() -> str: ...", "def kernel_set() -> str: ...\ndef kernel_sets() -> str: ...",
     "kernel_sets: in the stub, not in the module"),
    ("        out: _Records | None = None,\n        *,\n        threads: int = 0,\n        normals",
     "        out: _Records | None = None,\n        threads: int = 0,\n        *,\n        normals",
     "Scene.intersect: parameters differ"),
    ("    @property\n    def meshes(self) -> int: ...", "    def meshes(self) -> int: ...",
     "Scene.meshes: a function in the stub, a property in the module"),
])
def test_the_comparison_catches_a_planted_mismatch(old, new, expect):
    planted = _plant((SOURCE / "_arbor.pyi").read_text(), old, new)
    problems, _ = differences(planted, arbor._arbor)
    assert any(p.startswith(expect) for p in problems), problems


def test_the_comparison_catches_a_name_missing_from_the_package_stub():
    planted = _plant((SOURCE / "__init__.pyi").read_text(), "hit_normal_dtype: Final[np.dtype[np.void]]\n", "")
    problems, _ = differences(planted, arbor)
    assert problems == ["hit_normal_dtype: in the module, not in the stub"]


def _public_routines():
    """(name, object with the docstring, function whose parameters it must name or None)."""
    yield "arbor.read_rays", arbor.read_rays, arbor.read_rays
    yield "arbor.kernel_set", arbor.kernel_set, arbor.kernel_set
    for name, raw in vars(arbor.Scene).items():
        if name.startswith("_") and name != "__init__":
            continue
        if isinstance(raw, property):
            yield f"arbor.Scene.{name}", raw, None
        else:
            yield f"arbor.Scene.{name}", getattr(arbor.Scene, name), getattr(arbor.Scene, name)


@pytest.mark.parametrize("name, obj, fn", list(_public_routines()), ids=lambda x: x if isinstance(x, str) else "")
def test_every_public_function_has_a_docstring_naming_its_parameters(name, obj, fn):
    doc = inspect.getdoc(obj) or ""
    # pybind11 puts the signature on the first line: the text after it is the docstring.
    short = name.split(".")[-1]
    body = doc.split("\n", 1)[1] if doc.startswith(short + "(") else doc
    assert len(body.strip()) > 20, (name, doc)
    if fn is not None:
        for param, _, _ in signature_of(fn):
            if param != "self":
                assert param in body, (name, param)
    # help() shows it.
    assert body.strip().splitlines()[0] in pydoc.render_doc(obj, renderer=pydoc.plaintext)
