"""Builds the Python package `arbor` with CMake (docs/python.md, "Installing the package").

pyproject.toml holds the metadata. This file adds the version, read from the top CMakeLists.txt's
project() so that CMake's project version stays the only source of it; a build_ext that has CMake
build the extension and libarbor instead of compiling sources itself; and the package's files
(python/arbor/: __init__.py and any *.pyi and py.typed).

Environment:
  ARBOR_CMAKE_BUILD_DIR   reuse this configured CMake build folder of this checkout (absolute, or
                          relative to the checkout; e.g. build/release): it is only built
                          (`cmake --build DIR --target arbor_python`), not configured, so the
                          package gets that build's flags (release: -march=native), not the
                          portable ones. Without it: a portable build from scratch in build/pip.
  ARBOR_CMAKE_ARGS        more arguments for that from-scratch configure (shell-quoted)
  CMAKE_BUILD_PARALLEL_LEVEL  parallel jobs (read by `cmake --build` itself)
"""
import os
import pathlib
import re
import shlex
import shutil
import subprocess
import sys
import sysconfig

from setuptools import Extension, setup
from setuptools.command.build import build
from setuptools.command.build_ext import build_ext
from setuptools.errors import ExecError, SetupError

ROOT = pathlib.Path(__file__).resolve().parent
# The install component of python/CMakeLists.txt holding the package's binaries.
COMPONENT = "python_package"


def cmake_version():
    """The version in the top CMakeLists.txt's `project(arbor VERSION x.y.z ...)`."""
    text = (ROOT / "CMakeLists.txt").read_text()
    found = re.search(r"^project\(arbor\s+VERSION\s+(\d+(?:\.\d+)*)\b", text, re.M)
    if not found:
        sys.exit(f"setup.py: {ROOT / 'CMakeLists.txt'}: no `project(arbor VERSION x.y.z ...)` line")
    return found.group(1)


def reused_build_dir():
    """ARBOR_CMAKE_BUILD_DIR resolved and checked, or None when unset or empty."""
    value = os.environ.get("ARBOR_CMAKE_BUILD_DIR", "")
    if not value:
        return None
    path = (ROOT / value).resolve()
    cache = path / "CMakeCache.txt"
    if not cache.is_file():
        raise SetupError(f"ARBOR_CMAKE_BUILD_DIR={value}: not a configured CMake build folder (no "
                         f"{cache}); configure one (cmake --preset release) or unset it to build from scratch")
    entries = dict(re.findall(r"^([\w.-]+):\w+=(.*)$", cache.read_text(), re.M))
    home = entries.get("CMAKE_HOME_DIRECTORY")
    if not home or pathlib.Path(home).resolve() != ROOT:
        raise SetupError(f"ARBOR_CMAKE_BUILD_DIR={value}: configured for the sources in {home or 'an unknown folder'}, "
                         f"not for this checkout ({ROOT})")
    on = lambda name: entries.get(name, "OFF").upper() in ("ON", "TRUE", "YES", "Y", "1")
    if not on("ARBOR_PYTHON") or on("ARBOR_SANITIZE") or on("ARBOR_TSAN"):
        raise SetupError(f"ARBOR_CMAKE_BUILD_DIR={value}: that build has no Python module (ARBOR_PYTHON is off, "
                         f"or it is a sanitizer build)")
    return path


def run(cmd):
    """Runs a command, its output going to ours; a failure is one line naming it."""
    print("arbor:", shlex.join(str(c) for c in cmd), flush=True)
    try:
        status = subprocess.run([str(c) for c in cmd]).returncode
    except FileNotFoundError:
        raise ExecError(f"{cmd[0]}: not found on PATH (scripts/setup_deps.sh installs it)") from None
    if status != 0:
        raise ExecError(f"`{shlex.join(str(c) for c in cmd)}` failed with exit status {status} (its output is above)")


class CleanBuild(build):
    """Empties the package's folder in build/lib.* first: setuptools copies into it without removing
    anything, and a stub deleted since, or another version's libarbor, would go into the wheel."""

    def run(self):
        shutil.rmtree(pathlib.Path(self.build_lib) / "arbor", ignore_errors=True)
        super().run()


class CMakeBuild(build_ext):
    """Builds the extension `arbor._arbor` by building CMake's target arbor_python, then copies
    the module and libarbor, as CMake's install component `python_package` lays them out (the
    module's RUNPATH is $ORIGIN), into the package folder that the wheel is made from."""

    def build_extension(self, ext):
        build_dir = REUSED_BUILD_DIR
        if build_dir is None:
            build_dir = ROOT / "build" / "pip"
            self.configure(build_dir)
        jobs = ["--parallel", str(self.parallel)] if self.parallel else []
        run(["cmake", "--build", build_dir, "--target", "arbor_python", *jobs])

        staging = pathlib.Path(self.build_temp).resolve() / "cmake-install"
        shutil.rmtree(staging, ignore_errors=True)
        run(["cmake", "--install", build_dir, "--component", COMPONENT, "--prefix", staging])
        built = sorted((staging / "arbor").glob("*")) if (staging / "arbor").is_dir() else []
        module = pathlib.Path(self.get_ext_fullpath(ext.name))
        modules = [p for p in built if p.name.startswith("_arbor")]
        if [p.name for p in modules] != [module.name]:
            raise SetupError(f"{build_dir} installs the module(s) {[p.name for p in modules]}, but this Python "
                             f"({sys.executable}) loads {module.name}: configure that build with this Python "
                             f"(-DPython3_EXECUTABLE) or unset ARBOR_CMAKE_BUILD_DIR")

        module.parent.mkdir(parents=True, exist_ok=True)
        for path in built:
            shutil.copy2(path, module.parent / path.name)

    def configure(self, build_dir):
        """The portable build (every x86-64 CPU; the SIMD kernels chosen at run time), with only
        what the package holds: no tests, MPI front end or Embree peer."""
        cmd = ["cmake", "-S", ROOT, "-B", build_dir, "-DCMAKE_BUILD_TYPE=Release", "-DARBOR_PORTABLE=ON",
               "-DBUILD_TESTING=OFF", "-DARBOR_MPI=OFF", "-DARBOR_EMBREE=OFF",
               f"-DPython3_EXECUTABLE={sys.executable}"]
        if not (build_dir / "CMakeCache.txt").exists() and shutil.which("ninja"):
            cmd += ["-G", "Ninja"]
        run(cmd + shlex.split(os.environ.get("ARBOR_CMAKE_ARGS", "")))


try:
    REUSED_BUILD_DIR = reused_build_dir()
except SetupError as error:
    sys.exit(f"error: {error}")
# setuptools' own folders (lib.*, temp.*, bdist.*) go inside the CMake build folder in use, so a
# test that reuses build/release and a user's build/pip never share one.
BUILD_BASE = (REUSED_BUILD_DIR or ROOT / "build" / "pip") / "python-package"

setup(
    version=cmake_version(),
    packages=["arbor"],
    package_dir={"": "python"},
    # The type stubs and the PEP 561 marker, whichever of them python/arbor/ holds.
    package_data={"arbor": ["*.pyi", "py.typed"]},
    include_package_data=False,
    ext_modules=[Extension("arbor._arbor", sources=[])],
    cmdclass={"build": CleanBuild, "build_ext": CMakeBuild},
    options={"build": {"build_base": str(BUILD_BASE)}},
)
