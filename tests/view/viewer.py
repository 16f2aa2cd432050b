"""Starts and stops `arbor view` for the tests: a free port (--port 0), the address read from the
first line of its output, stderr collected, every wait bounded."""
import json
import os
import select
import signal
import subprocess
import threading
import time
import urllib.parse

from ws_client import BINARY, TEXT, WebSocket


class Viewer:
    def __init__(self, arbor, *args, timeout=30):
        self.proc = subprocess.Popen([arbor, "view", "--port", "0", *args], stdout=subprocess.PIPE,
                                     stderr=subprocess.PIPE, text=True)
        self.stderr_lines = []
        threading.Thread(target=self._drain, daemon=True).start()
        ready = select.select([self.proc.stdout], [], [], timeout)[0]
        if not ready:
            self.kill()
            raise RuntimeError(f"arbor view printed no address in {timeout} s: {self.stderr()}")
        self.url = self.proc.stdout.readline().strip()
        u = urllib.parse.urlparse(self.url)
        if u.scheme != "http" or not u.port:
            self.kill()
            raise RuntimeError(f"first line is not an address: {self.url!r} ({self.stderr()})")
        self.host, self.port = u.hostname, u.port

    def _drain(self):
        for line in self.proc.stderr:
            self.stderr_lines.append(line.rstrip("\n"))

    def stderr(self):
        return "\n".join(self.stderr_lines)

    def wait_log(self, needle, timeout=20):
        """The first stderr line containing needle, waiting up to timeout seconds."""
        end = time.time() + timeout
        while time.time() < end:
            for line in list(self.stderr_lines):
                if needle in line:
                    return line
            time.sleep(0.05)
        raise AssertionError(f"no stderr line with {needle!r} in {timeout} s:\n{self.stderr()}")

    def cpu_seconds(self):
        with open(f"/proc/{self.proc.pid}/stat") as f:
            fields = f.read().rsplit(")", 1)[1].split()
        return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")

    def connect(self, **kw):
        return Page(WebSocket(self.host, self.port, **kw))

    def stop(self, sig=signal.SIGINT, timeout=20):
        """Sends sig; returns the exit status (AssertionError if it does not exit in time)."""
        self.proc.send_signal(sig)
        try:
            return self.proc.wait(timeout)
        except subprocess.TimeoutExpired:
            self.kill()
            raise AssertionError(f"arbor view did not stop within {timeout} s of {sig!r}:\n{self.stderr()}")

    def kill(self):
        if self.proc.poll() is None:
            self.proc.kill()
            self.proc.wait(10)


class Page:
    """A WebSocket client speaking the viewer's protocol (view/protocol.h) as the page does."""

    def __init__(self, ws):
        self.ws = ws
        op, data = ws.recv()
        assert op == TEXT, op
        self.hello = json.loads(data)
        assert self.hello["type"] == "hello", self.hello

    def send(self, message):
        self.ws.send_text(json.dumps(message))

    def next_frame(self, ack=True):
        """The next frame's figures and JPEG bytes (skipping text notes); acknowledged unless ack=False."""
        while True:
            op, data = self.ws.recv()
            if op == BINARY:
                n = int.from_bytes(data[:4], "little")
                figures = json.loads(data[4:4 + n])
                if ack:
                    self.send({"type": "ack", "frame": figures["frame"]})
                return figures, data[4 + n:]
            note = json.loads(data)
            if note["type"] == "error":
                raise AssertionError(f"server error: {note}")

    def next_text(self, kind):
        while True:
            op, data = self.ws.recv()
            if op == TEXT and json.loads(data)["type"] == kind:
                return json.loads(data)
            if op == BINARY:
                n = int.from_bytes(data[:4], "little")
                self.send({"type": "ack", "frame": json.loads(data[4:4 + n])["frame"]})
