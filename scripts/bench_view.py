#!/usr/bin/env python3
"""Frames per second of `arbor view` and its overhead against `arbor render` of the same frame.

For each model and integrator, ROUNDS rounds, interleaved: the viewer (one running server per
model, a WebSocket client that acknowledges every frame at once, as the page does) refines the
picture for FRAMES frames after WARMUP frames, and `arbor render` renders the same frame (same size,
1 spp, same integrator, structure and threads, no extra layers: the viewer computes none) in a
fresh process, REPEAT times. Reported per
(model, integrator): the viewer's frames per second (1 / median interval between frames arriving at
the client), the render's frames per second (1 / median of its "rendered in" seconds: the render
alone, without loading and building), the overhead per frame (median interval - median render)
and their ratio; each as the median over rounds with the range over rounds.
Accuracy beside the speed: the viewer's first 1-spp frame (JPEG, decoded with Pillow) against the
PNG of `arbor render --spp 1` of the same frame (same camera, seed 0), per pixel and channel in
8-bit levels: the mean and largest |difference| (JPEG's loss; a wrong frame would differ by far more).
Pillow is python3-pil, which python3-matplotlib (scripts/setup_deps.sh) depends on.
The load average is recorded before and after (a shared machine: the rounds are interleaved).
Usage: bench_view.py ARBOR MODEL [MODEL...] [--rounds 5] [--frames 20] [--threads 2] [--out FILE.md]
"""
import argparse
import io
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time

import numpy
from PIL import Image

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "view"))
from viewer import Viewer  # noqa: E402

ap = argparse.ArgumentParser()
ap.add_argument("arbor")
ap.add_argument("models", nargs="+")
ap.add_argument("--integrators", default="primary,direct")
ap.add_argument("--accel", default="bvh-sah")
ap.add_argument("--rounds", type=int, default=5)
ap.add_argument("--frames", type=int, default=20)
ap.add_argument("--warmup", type=int, default=3)
ap.add_argument("--repeat", type=int, default=5)
ap.add_argument("--threads", type=int, default=2)
ap.add_argument("--width", type=int, default=640)
ap.add_argument("--height", type=int, default=480)
ap.add_argument("--out")
args = ap.parse_args()


def viewer_round(page, integrator):
    if getattr(page, "pending", None):  # the frame left unacknowledged at the end of the last round
        page.send({"type": "ack", "frame": page.pending})
    page.send({"type": "settings", "integrator": integrator, "accel": args.accel, "width": args.width,
               "height": args.height, "spp": 4096, "threads": args.threads})
    # Settings equal to the last round's do not start the picture over; the camera (the scene's own,
    # as `arbor render` frames it) always does.
    page.send({"type": "camera", **page.hello["camera"]})
    # Frames of the previous settings may still come: skip until this integrator's first pass.
    while True:
        f, jpeg = page.next_frame()
        if f["integrator"] == integrator and f["samples"] == 1:
            page.first_jpeg = jpeg
            break
    for _ in range(args.warmup):
        page.next_frame()
    arrivals, render_ms, encode_ms = [], [], []
    for i in range(args.frames + 1):
        last = i == args.frames
        f, _ = page.next_frame(ack=not last)  # the last one unacknowledged: the viewer parks after one more pass
        arrivals.append(time.perf_counter())
        render_ms.append(f["render_ms"])
        encode_ms.append(f["encode_ms"])
    page.pending = f["frame"]
    intervals = [1000 * (b - a) for a, b in zip(arrivals, arrivals[1:])]
    time.sleep(0.5)
    return statistics.median(intervals), statistics.median(render_ms[1:]), statistics.median(encode_ms[1:])


def render_once(model, integrator, out):
    r = subprocess.run([args.arbor, "render", model, "--integrator", integrator, "--accel", args.accel,
                        "--width", str(args.width), "--height", str(args.height), "--spp", "1",
                        "--threads", str(args.threads), "--layers", "none", "-q", "--no-png", "-o", out],
                       capture_output=True, text=True, timeout=600, check=True)
    return 1000 * float(re.search(r"rendered in ([0-9.]+) s", r.stdout).group(1))


def frame_difference(jpeg, model, integrator):
    """Mean and max |viewer's first frame - `arbor render` PNG| in 8-bit levels."""
    png = os.path.join(tmp, "same-frame.png")
    subprocess.run([args.arbor, "render", model, "--integrator", integrator, "--accel", args.accel,
                    "--width", str(args.width), "--height", str(args.height), "--spp", "1",
                    "--threads", str(args.threads), "-q", "-o", png], capture_output=True, timeout=600, check=True)
    a = numpy.asarray(Image.open(io.BytesIO(jpeg)).convert("RGB"), dtype=numpy.int16)
    b = numpy.asarray(Image.open(png).convert("RGB"), dtype=numpy.int16)
    if a.shape != b.shape:
        raise SystemExit(f"viewer frame {a.shape} and render {b.shape} differ in size")
    d = numpy.abs(a - b)
    return float(d.mean()), int(d.max())


def load_average():
    with open("/proc/loadavg") as f:
        return " ".join(f.read().split()[:3])


load_before = load_average()
rows = []
tmp = tempfile.mkdtemp(prefix="bench-view-")
for model in args.models:
    v = Viewer(args.arbor, model, "--threads", str(args.threads), "--accel", args.accel)
    try:
        page = v.connect()
        for integrator in args.integrators.split(","):
            view_ms, view_render, view_encode, render_ms = [], [], [], []
            for r in range(args.rounds):
                iv, rm, em = viewer_round(page, integrator)
                view_ms.append(iv), view_render.append(rm), view_encode.append(em)
                render_ms.append(statistics.median(render_once(model, integrator, os.path.join(tmp, "x.exr"))
                                                   for _ in range(args.repeat)))
            diff = frame_difference(page.first_jpeg, model, integrator)
            rows.append((os.path.basename(model), integrator, view_ms, view_render, view_encode, render_ms, diff))
            print(os.path.basename(model), integrator, "viewer interval", [round(x, 1) for x in view_ms],
                  "render", [round(x, 1) for x in render_ms], flush=True)
        page.ws.close()
    finally:
        v.stop()


def med_range(xs, fmt="{:.1f}"):
    return f"{fmt.format(statistics.median(xs))} ({fmt.format(min(xs))}-{fmt.format(max(xs))})"


lines = [f"`{' '.join(sys.argv)}`", "", f"Load average (1, 5, 15 min) before: {load_before}; after: {load_average()}.", "",
         f"{args.width}x{args.height}, 1 spp per frame, {args.accel}, {args.threads} threads; median over "
         f"{args.rounds} interleaved rounds (range over rounds in parentheses); per round the viewer's median "
         f"of {args.frames} frame intervals and the median of {args.repeat} `arbor render` processes.", "",
         "| model | integrator | viewer fps | `arbor render` fps (render alone) | viewer ms/frame | of which: pass render ms | JPEG + tone ms | render ms | overhead ms/frame | viewer / render time | first frame vs render PNG: mean / max abs diff (8-bit) |",
         "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
for model, integ, vms, vr, ve, rms, diff in rows:
    fps = [1000 / x for x in vms]
    rfps = [1000 / x for x in rms]
    over = [a - b for a, b in zip(vms, rms)]
    ratio = [a / b for a, b in zip(vms, rms)]
    lines.append(f"| {model} | {integ} | {med_range(fps)} | {med_range(rfps)} | {med_range(vms)} | {med_range(vr)} | "
                 f"{med_range(ve)} | {med_range(rms)} | {med_range(over)} | {med_range(ratio, '{:.2f}')} | {diff[0]:.2f} / {diff[1]} |")
text = "\n".join(lines) + "\n"
print(text)
if args.out:
    with open(args.out, "w") as f:
        f.write(text)
