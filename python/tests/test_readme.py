"""The README's Python example, run as written (the model path made absolute)."""
import pathlib
import runpy

import numpy as np

from conftest import shared_models


def readme_example():
    """The ```python block under the README's heading "From Python"."""
    readme = (pathlib.Path(__file__).resolve().parents[2] / "README.md").read_text()
    section = readme[readme.index("## From Python"):]
    block = section[section.index("```python\n") + len("```python\n"):]
    return block[:block.index("```")]


def test_readme_example_renders_a_depth_image(tmp_path, monkeypatch):
    code = readme_example()
    spot = next(m for m in shared_models() if m.name == "spot.obj")
    assert '"../shared/scenes/models/spot.obj"' in code
    (tmp_path / "example.py").write_text(code.replace('"../shared/scenes/models/spot.obj"', repr(str(spot))))
    monkeypatch.chdir(tmp_path)
    runpy.run_path(str(tmp_path / "example.py"))
    data = (tmp_path / "depth.pgm").read_bytes()
    header = b"P5 640 480 255\n"
    assert data.startswith(header) and len(data) == len(header) + 640 * 480
    img = np.frombuffer(data[len(header):], np.uint8)
    assert 0.05 < np.count_nonzero(img) / img.size < 0.9 and img.max() == 255
