#!/usr/bin/env python3
"""`arbor info` and `arbor view` on scenes of instances (engine/mesh_instances.h). info on
tests/data/meshes/instances-five-nodes.gltf (an octahedron placed by five nodes: nested, mirrored,
non-uniformly scaled) counts 5 instances, 8 unique and 40 effective triangles (`triangles`, as the
flattened file numbers them), 6 vertices held and 30 as the flattened file holds them. `arbor view builtin:field:3`, nine placed models: the page's hello counts the placed (effective) triangles that `arbor info --json` counts,
and its box holds the field; frames come with the primary and the direct integrator (the
two-level structure traced, instance hits shaded); the cost integrator gets an error note; and the
server stops with exit 0.
Usage: instances_test.py ARBOR
"""
import json
import os
import signal
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from viewer import Viewer  # noqa: E402

ARBOR = sys.argv[1]
SCENE = "builtin:field:3"
failures = []


def check(cond, what):
    if not cond:
        failures.append(what)
        print("FAIL:", what)


FIVE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "data", "meshes", "instances-five-nodes.gltf")
five = json.loads(subprocess.run([ARBOR, "info", FIVE, "--json", "--accel", "bvh-sah"], capture_output=True, text=True,
                                 check=True).stdout)
for key, want in (("instances", 5), ("unique_triangles", 8), ("effective_triangles", 40), ("triangles", 40),
                  ("vertices", 30), ("unique_vertices", 6)):
    check(five[key] == want, f"info five-nodes: {key} {five[key]}, expected {want}")
check(five["bytes_per_effective_triangle"] < five["bytes_per_unique_triangle"], "info five-nodes: memory per triangle")

info = json.loads(subprocess.run([ARBOR, "info", SCENE, "--json"], capture_output=True, text=True, check=True).stdout)
check(info["instances"] == 9, f"info: 9 instances, got {info['instances']}")
check(info["effective_triangles"] > info["unique_triangles"], "info: more placed triangles than unique ones")

viewer = Viewer(ARBOR, SCENE, "--threads", "1")
try:
    page = viewer.connect()
    hello = page.hello
    check(hello["triangles"] == info["effective_triangles"],
          f"hello counts {hello['triangles']} triangles, info {info['effective_triangles']}")
    lo, hi = hello["bounds"]["lo"], hello["bounds"]["hi"]
    check(lo[0] <= -2.4 and hi[0] >= 2.4 and hi[1] > 0.5, f"hello's box holds the field: {lo} .. {hi}")
    for integrator in ("primary", "direct"):
        page.send({"type": "settings", "width": 64, "height": 48, "spp": 1, "integrator": integrator, "threads": 1})
        figures, jpeg = page.next_frame()
        check(jpeg[:2] == b"\xff\xd8", f"{integrator}: a JPEG frame")
    # The cost integrator cannot count through instances: the page gets an error note, and the
    # server still stops cleanly (a pass that threw once left a dangling pass behind: SIGSEGV).
    page.send({"type": "settings", "width": 64, "height": 48, "spp": 1, "integrator": "cost", "threads": 1})
    try:
        for _ in range(20):  # frames of the earlier settings may still be on their way
            figures, _ = page.next_frame()
            check(figures["integrator"] != "cost", "cost integrator on instances: a frame, expected an error note")
        check(False, "cost integrator on instances: no error note in 20 frames")
    except AssertionError as e:
        check("cannot count" in str(e), f"cost integrator on instances: {e}")
    status = viewer.stop(signal.SIGTERM)
    check(status == 0, f"exit status {status} after SIGTERM")
finally:
    viewer.kill()

if failures:
    print(f"{len(failures)} failure(s)\n{viewer.stderr()}")
    sys.exit(1)
print("view of instances: ok")
