"""mypy --strict passes on the README's Python example and on a typed program using every public
name (typed_usage.py, also run here), and fails on a program that misuses the API, which shows
that the check reads arbor's stubs rather than treating arbor as untyped."""
import os
import pathlib
import subprocess
import sys

import numpy as np
import pytest

import arbor
from conftest import shared_models
from test_readme import readme_example

HERE = pathlib.Path(__file__).resolve().parent


@pytest.fixture(scope="module")
def mypy_cache(tmp_path_factory):
    """One mypy cache for the module's runs: numpy's stubs are read once, not once per run."""
    return tmp_path_factory.mktemp("mypy_cache")


def mypy(cache, *files):
    env = dict(os.environ)
    env.pop("PYTHONPATH", None)  # mypy finds numpy where python3 has it
    where = pathlib.Path(arbor.__file__).resolve().parents[1]
    if where.name not in ("site-packages", "dist-packages"):
        env["MYPYPATH"] = str(where)  # a build tree's package; an installed one mypy finds itself
    return subprocess.run([sys.executable, "-m", "mypy", "--strict", "--no-color-output", "--cache-dir",
                           str(cache), *map(str, files)], capture_output=True, text=True, env=env)


def test_mypy_strict_passes_on_the_readme_example_and_the_typed_usage(tmp_path, mypy_cache):
    example = tmp_path / "readme_example.py"
    example.write_text(readme_example())
    run = mypy(mypy_cache, example, HERE / "typed_usage.py")
    assert run.returncode == 0, run.stdout + run.stderr
    assert "Success" in run.stdout


MISUSES = [
    ('scene.intersect(o, d, threads="2")', "threads"),
    ("scene.build(accel=None)", "accel"),
    ("h: str = scene.triangles", "str"),
    ("scene.intersect_all(o, d, 0.0, 1.0, 4, None)", "intersect_all"),
    ("scene.inside(o, method=3)", "method"),
]


@pytest.mark.parametrize("line, word", MISUSES)
def test_mypy_strict_fails_on_a_misuse(tmp_path, mypy_cache, line, word):
    bad = tmp_path / "bad.py"
    bad.write_text("import numpy as np\nimport arbor\n\nscene = arbor.Scene()\n"
                   "o = np.zeros((2, 3), np.float32)\nd = np.ones((2, 3), np.float32)\n" + line + "\n")
    run = mypy(mypy_cache, bad)
    assert run.returncode == 1 and "bad.py:7: error" in run.stdout and word in run.stdout, run.stdout + run.stderr


# Misuses of the winding calls, checked in one mypy run (each costs seconds): each line is an error.
WINDING_MISUSES = [
    ('scene.signed_distance(o, "ray")', "signed_distance"),
    ("w: list[float] = scene.winding_number(o)", "floating[_64Bit]"),
    ("scene.closed = True", "closed"),
    ("scene.inside(o, exact=1.5)", "exact"),
]


def test_mypy_strict_fails_on_each_winding_misuse(tmp_path, mypy_cache):
    bad = tmp_path / "bad.py"
    head = ("import numpy as np\nimport arbor\n\nscene = arbor.Scene()\n"
            "o = np.zeros((2, 3), np.float32)\nd = np.ones((2, 3), np.float32)\n")
    bad.write_text(head + "".join(line + "\n" for line, _ in WINDING_MISUSES))
    run = mypy(mypy_cache, bad)
    assert run.returncode == 1, run.stdout + run.stderr
    errors = run.stdout.splitlines()
    for n, (line, word) in enumerate(WINDING_MISUSES, start=7):
        at = [e for e in errors if f"bad.py:{n}: error" in e]
        assert at and any(word in e for e in at), (line, run.stdout)


def test_the_typed_usage_runs_and_returns_what_it_states(tmp_path):
    sys.path.insert(0, str(HERE))
    try:
        import typed_usage
    finally:
        sys.path.remove(str(HERE))
    spot = next(m for m in shared_models() if m.name == "spot.obj")
    rec = np.zeros((3, 8), np.float32)
    rec[:, 2], rec[:, 6], rec[:, 7] = 5.0, -1.0, np.inf
    path = tmp_path / "r.rays"
    path.write_bytes(b"RAYS" + (1).to_bytes(4, "little") + (3).to_bytes(8, "little") + rec.tobytes())
    got = typed_usage.use_everything(spot, path)
    assert got["hits"].dtype == arbor.hit_dtype and got["with_normals"].dtype == arbor.hit_normal_dtype
    assert got["hits"]["t"][0] == pytest.approx(1.0) and got["hits"]["prim"][1] == arbor.MISS
    assert got["occ"].dtype == np.bool_ and list(got["occ"]) == [True, False]
    assert got["all_hits"].shape == (2, 4) and got["counts"].dtype == np.int32
    assert got["grid_hits"].shape == (3, 4) and got["near"].shape == () and got["nears"].shape == (2,)
    assert got["ins"].dtype == np.bool_ and got["file_hits"].shape == (3,)
    assert got["triangles"] == 4 and got["meshes"] == 1 and got["geom"] == 0
    assert got["winding"].dtype == np.float64 and abs(got["winding"][0] - 1) < 0.05 and abs(got["winding"][1]) < 0.05
    assert list(got["ins_winding"]) == [True, False] and got["closed"] is True
    assert got["signed"].dtype == np.float32 and got["signed"][0] < 0 < got["signed"][1]
