"""Chromium driven over the DevTools protocol (CDP) with the small WebSocket client of this
folder: Debian's headless chromium, a fresh profile, every wait bounded."""
import base64
import json
import queue
import re
import shutil
import subprocess
import tempfile
import threading
import time
import urllib.parse

from ws_client import WebSocket

FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync",
         "--disable-extensions", "--disable-default-apps", "--mute-audio", "--remote-debugging-port=0"]


class Browser:
    def __init__(self, executable="/usr/bin/chromium", window=(1100, 800), timeout=30):
        self.profile = tempfile.mkdtemp(prefix="arbor-chromium-")
        self.proc = subprocess.Popen([executable, *FLAGS, f"--user-data-dir={self.profile}",
                                      f"--window-size={window[0]},{window[1]}", "about:blank"],
                                     stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        self.log, found = [], queue.Queue()

        def drain():
            for line in self.proc.stderr:
                self.log.append(line.rstrip("\n"))
                m = re.search(r"DevTools listening on (ws://\S+)", line)
                if m:
                    found.put(m.group(1))
        threading.Thread(target=drain, daemon=True).start()
        try:
            url = urllib.parse.urlparse(found.get(timeout=timeout))
        except queue.Empty:
            self.close()
            raise RuntimeError("chromium did not start its DevTools endpoint:\n" + "\n".join(self.log[-20:]))
        self.ws = WebSocket(url.hostname, url.port, path=url.path, timeout=timeout)
        self.next_id = 0

    def call(self, method, params=None, session=None, timeout=30):
        self.next_id += 1
        message = {"id": self.next_id, "method": method, "params": params or {}}
        if session:
            message["sessionId"] = session
        self.ws.send_text(json.dumps(message))
        end = time.time() + timeout
        while time.time() < end:
            reply = json.loads(self.ws.recv()[1])
            if reply.get("id") == self.next_id:
                if "error" in reply:
                    raise RuntimeError(f"{method}: {reply['error']}")
                return reply.get("result", {})
        raise TimeoutError(f"{method}: no answer in {timeout} s")

    def open(self, url):
        """A new tab at url; returns its CDP session id."""
        target = self.call("Target.createTarget", {"url": url})["targetId"]
        return self.call("Target.attachToTarget", {"targetId": target, "flatten": True})["sessionId"]

    def evaluate(self, session, expression):
        r = self.call("Runtime.evaluate", {"expression": expression, "returnByValue": True, "awaitPromise": True},
                      session)
        if "exceptionDetails" in r:
            raise RuntimeError(f"{expression}: {r['exceptionDetails']}")
        return r["result"].get("value")

    def wait_for(self, session, condition, timeout=30, what=None):
        """Polls the JavaScript expression until it is truthy; returns its value."""
        end = time.time() + timeout
        while time.time() < end:
            v = self.evaluate(session, condition)
            if v:
                return v
            time.sleep(0.1)
        raise AssertionError(f"timed out after {timeout} s waiting for {what or condition}")

    def drag(self, session, x0, y0, dx, dy, steps=8, shift=False):
        mods = 8 if shift else 0
        self.call("Input.dispatchMouseEvent", {"type": "mousePressed", "x": x0, "y": y0, "button": "left",
                                               "clickCount": 1, "modifiers": mods}, session)
        for i in range(1, steps + 1):
            self.call("Input.dispatchMouseEvent", {"type": "mouseMoved", "x": x0 + dx * i / steps,
                                                   "y": y0 + dy * i / steps, "button": "left", "buttons": 1,
                                                   "modifiers": mods}, session)
            time.sleep(0.02)
        self.call("Input.dispatchMouseEvent", {"type": "mouseReleased", "x": x0 + dx, "y": y0 + dy,
                                               "button": "left", "clickCount": 1, "modifiers": mods}, session)

    def screenshot(self, session, path):
        data = self.call("Page.captureScreenshot", {"format": "png"}, session)["data"]
        with open(path, "wb") as f:
            f.write(base64.b64decode(data))

    def close(self):
        try:
            if getattr(self, "ws", None):
                self.call("Browser.close", timeout=5)
        except Exception:
            pass
        try:
            self.proc.wait(10)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait(10)
        shutil.rmtree(self.profile, ignore_errors=True)
