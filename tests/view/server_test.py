#!/usr/bin/env python3
"""`arbor view` without a browser (view/server.h): what it refuses and how it stops.

- Any path but / is 404, any method but GET/HEAD 405, a foreign Host 403; / is the page.
- A WebSocket from another Origin (or with a foreign Host) is refused with 403 before the
  handshake; the page's own Origin is accepted.
- An oversized message (whole or in fragments), a malformed one, a degenerate camera and a binary
  message each close that connection with its close code; a page connected all along keeps
  getting frames after each.
- Two pages at once both get frames; a page that disconnects in the middle of a long pass stops
  its work (the server's CPU goes idle, the log says the pass was cancelled).
- SIGTERM and SIGINT stop the server cleanly (exit 0) with pages open.
Usage: server_test.py ARBOR
"""
import os
import signal
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from viewer import Viewer  # noqa: E402
from ws_client import BINARY, Closed, Refused, WebSocket, http_request  # noqa: E402

ARBOR = sys.argv[1]
failures = []


def check(cond, what):
    if not cond:
        failures.append(what)
        print("FAIL:", what)


def expect_close(page, code, what):
    try:
        for _ in range(50):  # frames may still be on their way before the close frame
            page.ws.recv()
        check(False, f"{what}: still open")
    except Closed as e:
        check(e.code == code, f"{what}: closed with {e.code} (expected {code}) {e.reason}")
    try:
        page.ws.recv()
        check(False, f"{what}: the connection goes on after the close frame")
    except (Closed, OSError):
        pass


def still_served(page, step):
    """The page connected all along gets a new picture after a camera move."""
    cam = page.hello["camera"]
    eye = [cam["eye"][0] + 0.01 * step, cam["eye"][1], cam["eye"][2]]
    page.send({"type": "camera", "eye": eye, "look_at": cam["look_at"], "up": cam["up"], "fov": cam["fov"]})
    for _ in range(20):
        f, jpeg = page.next_frame()
        if f["samples"] == 1 and f["frame"] > 1:
            return f
    raise AssertionError("the good page got no new picture")


def http_checks(v):
    h = f"{v.host}:{v.port}"
    status, head, body = http_request(v.host, v.port, f"GET / HTTP/1.1\r\nHost: {h}\r\n\r\n".encode())
    check(status == 200 and b"<title>arbor view</title>" in body, f"GET / -> {status}")
    check("Content-Security-Policy:" in head and "X-Frame-Options: DENY" in head, "page headers")
    for path in ["/etc/passwd", "/../../../../etc/passwd", "/%2e%2e/%2e%2e/etc/passwd", "/index.html", "/ws",
                 "/favicon.ico", "//etc/passwd"]:
        status, _, body = http_request(v.host, v.port, f"GET {path} HTTP/1.1\r\nHost: {h}\r\n\r\n".encode())
        check(status in (400, 404) and b"root:" not in body, f"GET {path} -> {status}")
    for method in ["POST", "PUT", "DELETE", "OPTIONS"]:
        status, _, _ = http_request(v.host, v.port, f"{method} / HTTP/1.1\r\nHost: {h}\r\nContent-Length: 0\r\n\r\n".encode())
        check(status == 405, f"{method} / -> {status}")
    status, _, _ = http_request(v.host, v.port, f"GET / HTTP/1.1\r\nHost: evil.example:{v.port}\r\n\r\n".encode())
    check(status == 403, f"GET / with a foreign Host -> {status}")


def origin_checks(v):
    for origin, host in [("http://evil.example", None), (f"http://localhost.evil.example:{v.port}", None),
                         (f"https://{v.host}:{v.port}", None), ("null", None), (None, f"evil.example:{v.port}")]:
        try:
            WebSocket(v.host, v.port, origin=origin, host_header=host).close()
            check(False, f"WebSocket with Origin {origin}, Host {host} was accepted")
        except Refused as e:
            check(e.status == 403, f"WebSocket with Origin {origin}, Host {host} -> HTTP {e.status}")
    own = v.connect(origin=f"http://{v.host}:{v.port}")
    check(own.hello["type"] == "hello", "the page's own Origin is accepted")
    own.ws.close()
    v.wait_log("refused a WebSocket from 127.0.0.1: Origin 'http://evil.example'")


def message_checks(v, good):
    cases = [
        ("oversized", lambda p: p.ws.send_text('{"type":"ack","frame":1}' + " " * 5000), 1009),
        ("oversized in fragments", lambda p: [p.ws.send_frame(0x1 if i == 0 else 0x0, b" " * 2000, fin=i == 2)
                                              for i in range(3)], 1009),
        ("not JSON", lambda p: p.ws.send_text("hello?"), 1008),
        ("unknown type", lambda p: p.ws.send_text('{"type":"open","path":"/etc/passwd"}'), 1008),
        ("unknown field", lambda p: p.ws.send_text('{"type":"settings","scene":"/etc/passwd"}'), 1008),
        ("out of range", lambda p: p.ws.send_text('{"type":"settings","width":100000}'), 1008),
        ("degenerate camera", lambda p: p.ws.send_text(
            '{"type":"camera","eye":[1,1,1],"look_at":[1,1,1],"up":[0,1,0],"fov":40}'), 1008),
        ("binary", lambda p: p.ws.send_frame(BINARY, b"\x00\x01"), 1003),
    ]
    for step, (what, attack, code) in enumerate(cases, 1):
        bad = v.connect()
        attack(bad)
        expect_close(bad, code, what)
        f = still_served(good, step)
        check(f["samples"] == 1, f"after '{what}' the good page still gets pictures")
    v.wait_log("closed with 1009: message longer than 4096 bytes")


def two_pages(v):
    a, b = v.connect(), v.connect()
    for p in (a, b):
        p.send({"type": "settings", "width": 96, "height": 64, "spp": 3, "integrator": "primary"})
    got = {id(a): 0, id(b): 0}
    for _ in range(3):
        for p in (a, b):
            f, jpeg = p.next_frame()
            check(jpeg[:2] == b"\xff\xd8", "frames are JPEG")
            got[id(p)] += 1
    check(all(n == 3 for n in got.values()), f"two pages at once: {got}")
    a.ws.close(), b.ws.close()


def disconnect_mid_frame(v):
    # brute force at the largest image on one thread: a pass of minutes (26k triangles x 2.3M rays)
    p = v.connect()
    p.send({"type": "settings", "accel": "brute", "integrator": "primary", "width": 1920, "height": 1200, "threads": 1})
    # The page's first pass (the server's default structure) may start before these settings
    # arrive and is not cancelled by them (a first pass always finishes); wait for brute's own
    # build note, so the pass running below is the long one.
    while p.next_text("building")["accel"] != "brute":
        pass
    time.sleep(0.3)
    cpu = v.cpu_seconds()
    time.sleep(1.0)
    rate_during = v.cpu_seconds() - cpu  # CPU seconds per second while the pass runs (the machine may be busy)
    p.ws.sock.close()  # gone without a close frame, as a killed tab
    # The rate is measured once the server has seen the disconnect (on a loaded machine that can
    # take longer than a fixed sleep); a pass that goes on after it is caught either way.
    line = v.wait_log(f"client {p.hello['client']} (127.0.0.1) disconnected")
    check(" 1 cancelled" in line, f"the long pass was cancelled: {line}")
    time.sleep(0.3)
    cpu = v.cpu_seconds()
    time.sleep(1.0)
    rate_after = v.cpu_seconds() - cpu
    check(rate_during > 0.05, f"the long pass was not running ({rate_during:.2f} CPU s/s)")
    check(rate_after < 0.3 * rate_during,
          f"after the page left the server still used {rate_after:.2f} CPU s/s ({rate_during:.2f} during the pass)")


def command_line(v):
    """A port in use is a clear one-line error (exit 1); a bad --listen an option error (exit 2)."""
    for extra, status, needle in [(["--port", str(v.port)], 1, f"cannot listen on 127.0.0.1:{v.port}"),
                                  (["--listen", "999.1.1.1"], 2, "--listen"), (["--port", "70000"], 2, "--port"),
                                  (["--accel", "auto"], 2, "--accel")]:
        r = subprocess.run([ARBOR, "view", *extra], capture_output=True, text=True, timeout=30)
        lines = r.stderr.strip().splitlines()
        check(r.returncode == status and len(lines) == 1 and needle in r.stderr and r.stdout == "",
              f"arbor view {' '.join(extra)} -> exit {r.returncode}, stderr {r.stderr!r}")


for sig in (signal.SIGTERM, signal.SIGINT):
    v = Viewer(ARBOR, "--threads", "2")
    try:
        good = v.connect()
        good.send({"type": "settings", "width": 128, "height": 96, "spp": 4})
        good.next_frame()
        if sig == signal.SIGTERM:
            http_checks(v)
            origin_checks(v)
            message_checks(v, good)
            two_pages(v)
            command_line(v)
            disconnect_mid_frame(v)
        status = v.stop(sig)  # with a page still open
        check(status == 0, f"exit status {status} after {sig!r}")
        check(any("stopped" in line for line in v.stderr_lines), f"no 'stopped' line after {sig!r}")
    finally:
        v.kill()
    if failures:
        print(v.stderr())
        break

print("view server tests:", "FAILED" if failures else "passed")
sys.exit(1 if failures else 0)
