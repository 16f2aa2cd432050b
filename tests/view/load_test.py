#!/usr/bin/env python3
"""`arbor view` under load (issue 35): idle connections cost nothing and time out, and many pages
at once keep no new page out. Loopback only; every count and every wait is bounded.

1. Idle: 200 TCP connections that send nothing add at most 8 MB to the server's VmRSS; a new
   page's GET / answers within 2 s, and a new WebSocket client gets its first frame within
   FIRST_FRAME_S (5 s; 15 s in sanitized builds).
2. Load: 50 WebSocket clients at once (a child process: 50 tabs), each asking for frames as the
   page does (its settings, then a camera move every second, every frame acknowledged); once all
   have frames, 200 fresh idle connections. With all of them open: GET / within 2 s (3 tries), a
   new client's first frame within FIRST_FRAME_S (3 tries), the server's VmRSS at most 600 MB
   (2000 MB in sanitized builds) throughout, and each of the 50 got new pictures after its first
   (its camera moves were served).
3. Going away: the 50 close; the 200 idle ones and 5 clients trickling a request head a byte at a
   time are left to the server, which closes each within its head timeout (10 s, view/connections.h)
   + 3 s of its accept. The connection count (sockets in /proc/PID/fd besides the listener) returns
   to zero, and the server still serves a page and a first frame.
4. The cap: 512 + 64 idle connections: the server keeps at most its cap (512) open, dropping the
   oldest, and GET / still answers within 2 s; afterwards the count returns to zero.
5. SIGTERM: exit 0, and no sanitizer report on stderr (in the ASan build: no leak).
Stops at the first phase that fails; prints its figures either way.
Usage: load_test.py ARBOR [--sanitized]
"""
import argparse
import json
import multiprocessing
import os
import re
import resource
import select
import signal
import socket
import sys
import threading
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from viewer import Page, Viewer  # noqa: E402
from ws_client import BINARY, TEXT, WebSocket, http_request  # noqa: E402

IDLE, PAGES, TRICKLE = 200, 50, 5
CAP = 512           # the server's default --max-connections
HEAD_TIMEOUT = 10   # seconds a connection has for its request head (view/connections.h)
GET_S = 2.0         # a new page's GET / answers within this, under any of the loads here
IDLE_RSS_MB = 8     # what 200 idle connections may add to the server's VmRSS, in any build
PAGE_SETTINGS = {"type": "settings", "width": 64, "height": 48, "spp": 4, "integrator": "primary", "threads": 1}


def sockets(pid):
    """Sockets the process holds (its listener and its connections)."""
    n = 0
    for fd in os.listdir(f"/proc/{pid}/fd"):
        try:
            n += os.readlink(f"/proc/{pid}/fd/{fd}").startswith("socket:")
        except OSError:
            pass  # closed while listing
    return n


def rss_mb(pid):
    with open(f"/proc/{pid}/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024
    return 0.0


class RssWatch(threading.Thread):
    """The largest VmRSS seen, sampled every 50 ms."""

    def __init__(self, pid):
        super().__init__(daemon=True)
        self.pid, self.peak, self.running = pid, 0.0, True
        self.start()

    def run(self):
        while self.running:
            try:
                self.peak = max(self.peak, rss_mb(self.pid))
            except OSError:
                return
            time.sleep(0.05)


def get_page(v, timeout):
    """Seconds until a new page's GET / has the whole page, or None (refused, cut, or too slow)."""
    t0 = time.perf_counter()
    try:
        status, _, body = http_request(v.host, v.port, f"GET / HTTP/1.1\r\nHost: {v.host}:{v.port}\r\n\r\n".encode(),
                                       timeout=timeout)
    except (OSError, ValueError, IndexError):
        return None
    return time.perf_counter() - t0 if status == 200 and b"</html>" in body else None


def first_frame(v, timeout):
    """Seconds from a new WebSocket client's connect to its first frame, or None."""
    t0 = time.perf_counter()
    try:
        page = Page(WebSocket(v.host, v.port, timeout=timeout))
        page.send(PAGE_SETTINGS)
        page.next_frame()
        dt = time.perf_counter() - t0
        page.ws.close()
        return dt
    except Exception:  # refused, closed, timed out: no frame
        return None


def open_idle(v, n):
    return [(socket.create_connection((v.host, v.port), 10), time.monotonic()) for _ in range(n)]


def run_pages(host, port, n, ready, stop, results, timeout):
    """The child process: n pages at once, each in a thread, until `stop`; then their counts."""
    stats = [{"frames": 0, "pictures": 0, "error": None} for _ in range(n)]
    lock = threading.Lock()

    def page_loop(s):
        try:
            p = Page(WebSocket(host, port, timeout=timeout))
            p.send(PAGE_SETTINGS)
            cam, step, next_move = p.hello["camera"], 0, time.time() + 1.0
            while not stop.is_set():
                if time.time() >= next_move:  # a small camera move: a new picture, as a drag gives
                    step += 1
                    eye = [cam["eye"][0] + 0.001 * (step % 2), cam["eye"][1], cam["eye"][2]]
                    p.send({"type": "camera", "eye": eye, "look_at": cam["look_at"], "up": cam["up"], "fov": cam["fov"]})
                    next_move += 1.0
                if not p.ws.buf and not select.select([p.ws.sock], [], [], 0.1)[0]:
                    continue
                op, data = p.ws.recv()
                if op == BINARY:
                    k = int.from_bytes(data[:4], "little")
                    f = json.loads(data[4:4 + k])
                    p.send({"type": "ack", "frame": f["frame"]})
                    s["frames"] += 1
                    s["pictures"] += f["samples"] == 1
                    if s["frames"] == 1:
                        with lock:
                            ready.value += 1
                elif op == TEXT and b'"error"' in data:
                    s["error"] = data.decode()
            p.ws.close()
        except Exception as e:
            s["error"] = repr(e)

    threads = [threading.Thread(target=page_loop, args=(s,)) for s in stats]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    results.put(stats)


class Test:
    def __init__(self, arbor, slow):
        self.slow = slow
        self.first_frame_s = 5.0 * slow
        # 50 pages each render a first pass at the server's 640x480 before their own 64x48 settings
        # arrive: about 9 MB each (float sums, the pass, the 8-bit picture, the JPEG) when all overlap.
        self.rss_mb = 2000.0 if slow > 1 else 600.0
        self.failures, self.figures = [], []
        self.v = Viewer(arbor, "--threads", "1", "--max-clients", "64", "--integrator", "primary")
        self.pid = self.v.proc.pid
        self.listeners = sockets(self.pid)
        self.rss = RssWatch(self.pid)

    def check(self, cond, what):
        if not cond:
            self.failures.append(what)
            print("FAIL:", what, flush=True)

    def figure(self, name, value):
        self.figures.append((name, value))
        print(f"  {name}: {value}", flush=True)

    def connections(self):
        return sockets(self.pid) - self.listeners

    def wait_connections(self, n, timeout):
        """Seconds until the server holds at most n connections, or None."""
        t0 = time.monotonic()
        while time.monotonic() - t0 < timeout:
            if self.connections() <= n:
                return time.monotonic() - t0
            time.sleep(0.05)
        return None

    def probes(self, label, tries):
        gets = [get_page(self.v, 10) for _ in range(tries)]
        firsts = [first_frame(self.v, 10 * self.slow) for _ in range(tries)]
        fmt = lambda xs: ", ".join("none" if x is None else f"{1000 * x:.0f}" for x in xs)  # noqa: E731
        self.figure(f"{label}: GET / ms", fmt(gets))
        self.figure(f"{label}: first frame of a new client ms", fmt(firsts))
        self.check(all(x is not None and x <= GET_S for x in gets), f"{label}: GET / within {GET_S} s: {fmt(gets)} ms")
        self.check(all(x is not None and x <= self.first_frame_s for x in firsts),
                   f"{label}: a new client's first frame within {self.first_frame_s} s: {fmt(firsts)} ms")

    def idle_phase(self):
        print(f"1. {IDLE} idle connections", flush=True)
        self.probes("no other connection", 1)
        self.wait_connections(0, 10 * self.slow)
        time.sleep(0.5)  # the probe's page is freed on the server's stopper thread
        rss0 = rss_mb(self.pid)
        idle = open_idle(self.v, IDLE)
        time.sleep(0.3)
        grew = rss_mb(self.pid) - rss0  # before the probes: their page's session allocates far more
        self.figure(f"{IDLE} idle: connections the server holds", self.connections())
        self.figure(f"{IDLE} idle: VmRSS growth MB", f"{grew:.1f}")
        self.check(grew <= IDLE_RSS_MB, f"{IDLE} idle connections grew VmRSS by {grew:.1f} MB (bound {IDLE_RSS_MB} MB)")
        self.probes(f"{IDLE} idle", 1)
        for s, _ in idle:
            s.close()

    def load_phase(self):
        print(f"2. {PAGES} pages asking for frames and {IDLE} idle connections", flush=True)
        ctx = multiprocessing.get_context("spawn")
        ready, stop, results = ctx.Value("i", 0), ctx.Event(), ctx.Queue()
        child = ctx.Process(target=run_pages, args=(self.v.host, self.v.port, PAGES, ready, stop, results, 30 * self.slow))
        t0 = time.monotonic()
        child.start()
        while ready.value < PAGES and time.monotonic() - t0 < 60 * self.slow and child.is_alive():
            time.sleep(0.05)
        self.figure(f"seconds until all {PAGES} pages had a frame", f"{time.monotonic() - t0:.2f}")
        self.check(ready.value == PAGES, f"only {ready.value} of {PAGES} pages got a frame")
        idle = open_idle(self.v, IDLE)
        time.sleep(0.3)
        held = self.connections()
        self.figure("connections the server holds under load", held)
        self.check(held >= IDLE + PAGES, f"the server holds {held} connections, not the {IDLE + PAGES} opened")
        self.probes(f"{PAGES} pages + {IDLE} idle", 3)
        time.sleep(1.5)  # every page moves its camera at least once more
        stop.set()
        try:
            stats = results.get(timeout=30 * self.slow)
        except Exception:
            stats = None
        child.join(10)
        if child.is_alive():
            child.kill()
        self.check(stats is not None, "the pages' process gave no results")
        if stats:
            errors = [s["error"] for s in stats if s["error"]]
            self.check(not errors, f"{len(errors)} pages failed: {errors[:3]}")
            pictures = sorted(s["pictures"] for s in stats)
            self.figure("frames per page (min, median, max)",
                        f"{min(s['frames'] for s in stats)}, {sorted(s['frames'] for s in stats)[PAGES // 2]}, "
                        f"{max(s['frames'] for s in stats)}")
            # Pictures 1 and 2: the first pass at the server's settings, then the page's own settings.
            self.check(pictures[0] >= 3, f"a page got only {pictures[0]} pictures (camera moves not served)")
        self.figure("VmRSS peak so far MB", f"{self.rss.peak:.0f}")
        self.check(self.rss.peak <= self.rss_mb, f"VmRSS peaked at {self.rss.peak:.0f} MB (bound {self.rss_mb:.0f} MB)")
        return idle

    def going_away_phase(self, idle):
        print(f"3. the pages leave; {IDLE} idle and {TRICKLE} trickling connections are left to the server", flush=True)
        trickle = open_idle(self.v, TRICKLE)
        fresh = open_idle(self.v, 20) + trickle  # timed from now: the others may have closed while the probes ran
        left = idle + fresh
        stop = threading.Event()

        def drip():  # one byte of a request head every 0.5 s: the deadline is not moved by input
            head = b"GET / HTTP/1.1\r\nX-Slow: " + b"a" * 200
            for i in range(len(head)):
                for s, _ in trickle:
                    try:
                        s.send(head[i:i + 1])
                    except OSError:
                        pass
                if stop.wait(0.5):
                    return

        threading.Thread(target=drip, daemon=True).start()
        poller = select.poll()
        by_fd = {s.fileno(): (s, opened) for s, opened in left}
        for fd in by_fd:
            poller.register(fd, select.POLLIN)
        lasted = {}
        end = time.monotonic() + HEAD_TIMEOUT + 3 + 5 * (self.slow - 1)
        while len(lasted) < len(left) and time.monotonic() < end:
            for fd, _ in poller.poll(100):
                s, opened = by_fd[fd]
                try:
                    gone = s.recv(4096) == b""
                except OSError:
                    gone = True
                if gone:
                    lasted[fd] = time.monotonic() - opened
                    poller.unregister(fd)
        stop.set()
        times = sorted(lasted.values())
        fresh_times = sorted(lasted[s.fileno()] for s, _ in fresh if s.fileno() in lasted)
        for s, _ in left:
            s.close()
        if fresh_times:
            self.figure("fresh idle and trickling connections closed by the server after s (min, max)",
                        f"{fresh_times[0]:.2f}, {fresh_times[-1]:.2f}")
        if times:
            self.figure("idle and trickling connections closed by the server after s (min, max)",
                        f"{times[0]:.2f}, {times[-1]:.2f}")
        self.check(len(lasted) == len(left), f"the server closed only {len(lasted)} of {len(left)} idle connections "
                                             f"within {HEAD_TIMEOUT} s + 3 s")
        self.check(not times or times[0] >= HEAD_TIMEOUT - 1, f"an idle connection closed after {times[0]:.2f} s, "
                                                              f"before the head timeout of {HEAD_TIMEOUT} s")
        late = HEAD_TIMEOUT + 3 + 5 * (self.slow - 1)
        self.check(len(fresh_times) == len(fresh) and fresh_times[-1] <= late,
                   f"fresh idle connections closed after {fresh_times} s (bound {late} s)")
        t = self.wait_connections(0, 10 * self.slow)
        self.figure("connections left once all went away", self.connections())
        self.check(t is not None, f"{self.connections()} connections still open after all went away")
        self.probes("after all went away", 1)
        self.check(self.wait_connections(0, 10 * self.slow) is not None,
                   f"{self.connections()} connections open after the probes left")

    def cap_phase(self):
        n = CAP + 64
        print(f"4. {n} idle connections against the cap of {CAP}", flush=True)
        idle = open_idle(self.v, n)
        time.sleep(0.5)
        held = self.connections()
        self.figure(f"{n} idle: connections the server holds", held)
        self.check(held <= CAP, f"the server holds {held} connections, above its cap of {CAP}")
        t = get_page(self.v, 10)
        self.figure(f"{n} idle: GET / ms", "none" if t is None else f"{1000 * t:.0f}")
        self.check(t is not None and t <= GET_S, f"GET / at the cap took {t} s (bound {GET_S} s)")
        for s, _ in idle:
            s.close()
        self.check(self.wait_connections(0, 10 * self.slow) is not None,
                   f"{self.connections()} connections open after the idle ones closed")

    def stop_phase(self):
        print("5. SIGTERM", flush=True)
        status = self.v.stop(signal.SIGTERM, timeout=30 * self.slow)
        self.check(status == 0, f"exit status {status} after SIGTERM")
        log = self.v.stderr()
        self.check("Sanitizer" not in log and "runtime error:" not in log, "a sanitizer report on stderr")
        m = re.search(r"connections: (\d+) accepted, (\d+) closed .*, (\d+) dropped at the cap", log)
        self.check(m is not None, "no connection counts in the log at stop")
        if m:
            self.figure("connections accepted, timed out, dropped at the cap", ", ".join(m.groups()))
            self.check(int(m.group(3)) >= 64, f"only {m.group(3)} connections dropped at the cap")

    def run(self):
        self.idle_phase()
        idle = None if self.failures else self.load_phase()
        for phase in (lambda: self.going_away_phase(idle), self.cap_phase, self.stop_phase):
            if self.failures:
                break
            phase()
        self.rss.running = False
        self.figure("VmRSS peak MB", f"{self.rss.peak:.0f} (bound {self.rss_mb:.0f})")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("arbor")
    ap.add_argument("--sanitized", action="store_true", help="a sanitizer build: time and memory bounds x3 and x4")
    args = ap.parse_args()
    soft, hard = resource.getrlimit(resource.RLIMIT_NOFILE)
    if soft < 2048:  # the cap phase holds 600 sockets
        resource.setrlimit(resource.RLIMIT_NOFILE, (min(4096, hard), hard))
    t = Test(args.arbor, 3 if args.sanitized else 1)
    t0 = time.monotonic()
    try:
        t.run()
    except Exception as e:
        t.failures.append(f"{type(e).__name__}: {e}")
        print("FAIL:", t.failures[-1])
    finally:
        t.v.kill()
    print(f"view load test: {'FAILED' if t.failures else 'passed'} in {time.monotonic() - t0:.0f} s")
    if t.failures:
        print("\n".join(t.v.stderr_lines[-30:]))
    sys.exit(1 if t.failures else 0)


if __name__ == "__main__":
    main()
