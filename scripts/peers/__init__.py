"""The peers benchmark's parts (scripts/bench_peers.py): meshes and queries, the float64 referee,
and one adapter per library (arbor, Open3D's RaycastingScene, Embree 3 through ctypes, fcpw through a compiled shim when a checkout is given)."""
