"""Checks the installed package `arbor`, then runs the pytest suite on it in this same process.

    VENV/bin/python python_package_check.py --source CHECKOUT --tests DIR

Run by tests/python_package_test.sh with a virtual environment's python, from outside the source
and build trees and without PYTHONPATH. Fails (exit status not 0, one `FAIL:` line) unless `arbor`
is imported from the virtual environment; its version is the installed distribution's; the package
folder holds exactly __init__.py, the extension, libarbor (under the soname the extension needs)
and the stubs and py.typed that python/arbor/ holds; the extension's RUNPATH is $ORIGIN alone and
the dynamic loader finds libarbor beside it; and then the suite passes. The suite runs in this
process, so its `import arbor` is the module checked here.
"""
import argparse
import importlib.metadata
import pathlib
import re
import subprocess
import sys
import sysconfig


def fail(message):
    sys.exit(f"FAIL: {message}")


def dynamic_section(path):
    """(NEEDED names, RPATH/RUNPATH entries) of an ELF file, from readelf -d."""
    text = subprocess.run(["readelf", "-d", str(path)], check=True, capture_output=True, text=True).stdout
    needed = re.findall(r"\(NEEDED\)\s+Shared library: \[(.*)\]", text)
    paths = [p for found in re.findall(r"\((?:RPATH|RUNPATH)\)\s+Library r(?:un)?path: \[(.*)\]", text)
             for p in found.split(":")]
    return needed, paths


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--source", type=pathlib.Path, required=True, help="the checkout the package was built from")
    parser.add_argument("--tests", type=pathlib.Path, required=True, help="the copy of python/tests to run")
    args = parser.parse_args()

    if sys.prefix == sys.base_prefix:
        fail(f"{sys.executable} is not a virtual environment's python")
    try:
        import arbor
    except ImportError as error:
        fail(f"import arbor: {error}")

    venv = pathlib.Path(sys.prefix).resolve()
    package = pathlib.Path(arbor.__file__).resolve().parent
    if venv not in package.parents:
        fail(f"arbor was imported from {package}, not from the virtual environment {venv}")

    installed = importlib.metadata.version("arbor")
    if arbor.__version__ != installed:
        fail(f"arbor.__version__ is {arbor.__version__!r}, the installed distribution's version {installed!r}")

    module = package / ("_arbor" + sysconfig.get_config_var("EXT_SUFFIX"))
    if not module.is_file():
        fail(f"no extension {module.name} in {package}")
    needed, runpath = dynamic_section(module)
    libs = [n for n in needed if n.startswith("libarbor.so")]
    if len(libs) != 1:
        fail(f"{module.name} needs {needed}: expected exactly one libarbor.so*")
    if runpath != ["$ORIGIN"]:
        fail(f"{module.name} has the run path {runpath}, expected ['$ORIGIN'] alone")
    _, lib_runpath = dynamic_section(package / libs[0]) if (package / libs[0]).is_file() else ([], [])
    if any(p != "$ORIGIN" for p in lib_runpath):
        fail(f"{libs[0]} has the run path {lib_runpath}, which points outside the package")

    extras = {p.name for p in (args.source / "python" / "arbor").iterdir() if p.suffix == ".pyi" or p.name == "py.typed"}
    expected = {"__init__.py", module.name, libs[0]} | extras
    found = {p.name for p in package.iterdir() if p.name != "__pycache__"}
    if found != expected:
        fail(f"{package} holds {sorted(found)}, expected {sorted(expected)}")

    ldd = subprocess.run(["ldd", str(module)], check=True, capture_output=True, text=True).stdout
    if "not found" in ldd:
        fail(f"ldd {module.name}: a library is not found:\n{ldd}")
    resolved = re.search(rf"^\s*{re.escape(libs[0])} => (\S+)", ldd, re.M)
    if not resolved or pathlib.Path(resolved.group(1)).resolve() != (package / libs[0]).resolve():
        fail(f"ldd {module.name}: {libs[0]} resolves to {resolved.group(1) if resolved else 'nothing'}, "
             f"not to the copy in {package}")

    print(f"arbor {arbor.__version__} from {package} (kernel set {arbor.kernel_set()}); files {sorted(found)}",
          flush=True)
    import pytest
    status = pytest.main(["-q", "-p", "no:cacheprovider", str(args.tests)])
    if status != 0:
        fail(f"the pytest suite failed (exit status {int(status)}) on the package in {venv}")


if __name__ == "__main__":
    main()
