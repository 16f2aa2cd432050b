#!/usr/bin/env python3
"""`arbor view` in a real browser: Debian's headless chromium loads the page, frames arrive and
refine, a mouse drag moves the camera (the picture changes and starts over), switching the
structure rebuilds it (its frames say so, with a build time), the cost integrator shows its
scale, a second tab is served at the same time, and a screenshot is taken. Every wait is bounded
(about 15 s on the 2-core machine). Fails if chromium is missing.
Usage: browser_test.py ARBOR [--screenshot PNG] [--chromium PATH] [SCENE and other `arbor view` options...]
"""
import argparse
import os
import signal
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from cdp import Browser  # noqa: E402
from viewer import Viewer  # noqa: E402

ap = argparse.ArgumentParser()
ap.add_argument("arbor")
ap.add_argument("--screenshot")
ap.add_argument("--chromium", default="/usr/bin/chromium")
ap.add_argument("--integrator-for-screenshot", default="direct")
args, view_args = ap.parse_known_args()
if not os.access(args.chromium, os.X_OK):
    sys.exit(f"FAIL: no browser at {args.chromium} (scripts/setup_deps.sh installs Debian's chromium)")

CANVAS_HASH = """(() => { const c = document.getElementById('view');
  const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
  let h = 0; for (let i = 0; i < d.length; i += 3) h = (h * 31 + d[i]) >>> 0; return h; })()"""


def choose(b, tab, select, value):
    b.evaluate(tab, f"(() => {{ const s = document.getElementById('{select}'); s.value = '{value}';"
                    f" s.dispatchEvent(new Event('change')); return s.value; }})()")


def main():
    start = time.time()
    viewer = Viewer(args.arbor, "--threads", "2", *view_args)
    browser = None
    try:
        browser = Browser(args.chromium)
        tab = browser.open(viewer.url)
        b = browser
        # The page connects, the first frame arrives and refines.
        b.wait_for(tab, "window.arborView && arborView.frames >= 1", 20, "the first frame")
        hello = b.evaluate(tab, "arborView.hello")
        assert hello["type"] == "hello" and hello["triangles"] > 0, hello
        choose(b, tab, "spp", "1000")  # keep refining while the test runs
        b.wait_for(tab, "arborView.last.samples >= 3", 20, "three samples accumulated")
        first = b.evaluate(tab, "arborView.last")
        assert first["width"] == 640 and first["height"] == 480, first
        assert first["mrays"].get("primary", 0) > 0, first
        before = b.evaluate(tab, CANVAS_HASH)

        # Drag the camera: the picture starts over and changes.
        frames, pictures = b.evaluate(tab, "[arborView.frames, arborView.pictures]")
        rect = b.evaluate(tab, "(() => { const r = document.getElementById('view').getBoundingClientRect();"
                               " return [r.left + r.width / 2, r.top + r.height / 2]; })()")
        b.drag(tab, rect[0], rect[1], 160, 40)
        b.wait_for(tab, f"arborView.pictures > {pictures}", 20, "a new picture after the drag")
        after = b.evaluate(tab, CANVAS_HASH)
        assert after != before, "the picture did not change after the drag"
        b.drag(tab, rect[0], rect[1], -60, 30, shift=True)  # pan
        b.wait_for(tab, f"arborView.frames > {frames + 1}", 20, "a frame after the pan")

        # Switch the structure: it is built and its frames name it, with the build time.
        choose(b, tab, "accel", "kdtree")
        b.wait_for(tab, "arborView.last.accel === 'kdtree' && arborView.last.build_ms > 0", 20, "kd-tree frames")
        # The cost integrator: the picture changes and the scale's numbers are shown.
        choose(b, tab, "integrator", "cost")
        b.wait_for(tab, "arborView.last.integrator === 'cost' && arborView.last.cost_top >= 1", 20, "cost frames")
        legend = b.evaluate(tab, "document.getElementById('t4').textContent")
        assert legend.strip() != "", "the cost scale has no numbers"

        # A second tab at the same time gets its own frames while the first goes on.
        tab2 = b.open(viewer.url)
        b.wait_for(tab2, "window.arborView && arborView.frames >= 2", 20, "frames in the second tab")
        n1 = b.evaluate(tab, "arborView.frames")
        choose(b, tab, "accel", "bvh-sah")
        b.wait_for(tab, f"arborView.frames > {n1} && arborView.last.accel === 'bvh-sah'", 20, "the first tab goes on")
        assert b.evaluate(tab2, "arborView.closed") is None, "the second tab was closed"

        if args.screenshot:
            pictures = b.evaluate(tab, "arborView.pictures")
            b.evaluate(tab, "document.getElementById('reset').click()")  # the scene's own camera again
            b.wait_for(tab, f"arborView.pictures > {pictures}", 20, "a picture from the reset camera")
            choose(b, tab, "integrator", args.integrator_for_screenshot)
            choose(b, tab, "spp", "16")
            b.wait_for(tab, f"arborView.last.integrator === '{args.integrator_for_screenshot}' && "
                            "arborView.last.samples >= 16", 30, "16 samples for the screenshot")
            b.screenshot(tab, args.screenshot)
        errors = [line for line in b.log if "Uncaught" in line]
        assert not errors, errors
    finally:
        if browser:
            browser.close()
        status = viewer.stop(signal.SIGINT)
    assert status == 0, f"arbor view exited {status}"
    closed = [line for line in viewer.stderr_lines if "disconnected" in line]
    assert len(closed) >= 2, viewer.stderr()
    print(f"view browser test passed in {time.time() - start:.1f} s")


try:
    main()
except AssertionError as e:
    print("FAIL:", e)
    sys.exit(1)
