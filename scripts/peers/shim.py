"""Runs the calling script again with scripts/peers/mask_shim.c preloaded, so that Debian's Open3D
sees its rays (peers/open3d_peer.py says why); open3d_with_mask_shim() is the one call a benchmark
script makes."""
import os
import pathlib
import subprocess
import sys
import tempfile

SHIM_C = pathlib.Path(__file__).resolve().parent / "mask_shim.c"


def preload_mask_shim():
    """Compiles the shim into a temporary directory and re-executes sys.argv with it preloaded;
    returns at once when already preloaded."""
    if os.environ.get("ARBOR_PEERS_SHIM"):
        return
    tmp = tempfile.mkdtemp(prefix="arbor-peers-")
    so = os.path.join(tmp, "mask_shim.so")
    subprocess.run(["cc", "-shared", "-fPIC", "-O2", "-o", so, str(SHIM_C), "-ldl"], check=True)
    env = dict(os.environ, LD_PRELOAD=so, ARBOR_PEERS_SHIM=so)
    os.execve(sys.executable, [sys.executable] + sys.argv, env)


def open3d_with_mask_shim(prog):
    """Exits naming `prog` when Open3D cannot be imported, else preload_mask_shim()."""
    try:
        import open3d  # noqa: F401
    except ImportError:
        sys.exit(f"{prog}: Open3D is missing: apt-get install python3-open3d, and run with /usr/bin/python3")
    preload_mask_shim()
