"""tests/browser/cdp.py - a small client of the Chrome DevTools Protocol over a pipe
(chromium --remote-debugging-pipe: JSON messages separated by NUL bytes on file descriptors 3
and 4), so the browser tests need Python and Debian's chromium, nothing from the network.
"""
import json
import os
import select
import shutil
import subprocess
import tempfile
import time


class CDPError(Exception):
    pass


def find_chromium():
    """The chromium binary, or None."""
    for name in (os.environ.get("HOVOX_CHROMIUM"), "chromium", "chromium-browser"):
        if name:
            path = shutil.which(name)
            if path:
                return path
    return None


class Browser:
    """A headless chromium with no network of its own (no background requests, no updates)."""

    def __init__(self, binary, width=1400, height=1000):
        self.profile = tempfile.mkdtemp(prefix="hovox-chromium-")
        self.width, self.height = width, height
        to_chrome_r, self._to_chrome_w = os.pipe()
        self._from_chrome_r, from_chrome_w = os.pipe()

        def fds():  # the child's fds 3 and 4 (dup first: the pipe ends may sit at 3 or 4)
            a, b = os.dup(to_chrome_r), os.dup(from_chrome_w)
            os.dup2(a, 3)
            os.dup2(b, 4)

        args = [binary, "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
                "--disable-background-networking", "--disable-component-update", "--disable-sync",
                "--disable-default-apps", "--disable-extensions", "--force-color-profile=srgb",
                "--hide-scrollbars", "--mute-audio", "--user-data-dir=" + self.profile,
                "--window-size=%d,%d" % (width, height), "--remote-debugging-pipe", "about:blank"]
        self.log = open(os.path.join(self.profile, "chromium.log"), "w")
        self.proc = subprocess.Popen(args, preexec_fn=fds, close_fds=False, stdout=self.log, stderr=self.log,
                                     stdin=subprocess.DEVNULL)
        os.close(to_chrome_r)
        os.close(from_chrome_w)
        self._buf = b""
        self._id = 0
        self.events = []

    def close(self):
        try:
            self.send("Browser.close", timeout=5)
        except Exception:
            pass
        try:
            self.proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()
        for fd in (self._to_chrome_w, self._from_chrome_r):
            try:
                os.close(fd)
            except OSError:
                pass
        self.log.close()
        shutil.rmtree(self.profile, ignore_errors=True)

    def _read_message(self, deadline):
        while b"\0" not in self._buf:
            left = deadline - time.time()
            if left <= 0:
                raise CDPError("chromium did not answer in time")
            ready, _, _ = select.select([self._from_chrome_r], [], [], left)
            if not ready:
                continue
            chunk = os.read(self._from_chrome_r, 1 << 20)
            if not chunk:
                raise CDPError("chromium closed the pipe (see %s)" % self.log.name)
            self._buf += chunk
        msg, _, self._buf = self._buf.partition(b"\0")
        return json.loads(msg)

    def send(self, method, params=None, session=None, timeout=60):
        self._id += 1
        msg = {"id": self._id, "method": method, "params": params or {}}
        if session:
            msg["sessionId"] = session
        os.write(self._to_chrome_w, json.dumps(msg).encode() + b"\0")
        deadline = time.time() + timeout
        while True:
            m = self._read_message(deadline)
            if m.get("id") == self._id:
                if "error" in m:
                    raise CDPError("%s: %s" % (method, m["error"].get("message")))
                return m.get("result", {})
            self.events.append(m)

    def poll_events(self, seconds=0.0):
        """Read the events that arrive within `seconds`."""
        deadline = time.time() + seconds
        while True:
            try:
                if b"\0" not in self._buf:
                    ready, _, _ = select.select([self._from_chrome_r], [], [], max(0.0, deadline - time.time()))
                    if not ready:
                        return
                self.events.append(self._read_message(time.time() + 5))
            except CDPError:
                return

    def new_page(self):
        target = self.send("Target.createTarget", {"url": "about:blank"})["targetId"]
        session = self.send("Target.attachToTarget", {"targetId": target, "flatten": True})["sessionId"]
        return Page(self, session)


class Page:
    def __init__(self, browser, session):
        self.b, self.s = browser, session
        for domain in ("Page", "Runtime", "Network", "Log"):
            self.send(domain + ".enable")
        self.send("Emulation.setDeviceMetricsOverride",
                  {"width": browser.width, "height": browser.height, "deviceScaleFactor": 1, "mobile": False})

    def send(self, method, params=None, timeout=60):
        return self.b.send(method, params, self.s, timeout)

    def events(self, method):
        return [e["params"] for e in self.b.events if e.get("method") == method and e.get("sessionId") == self.s]

    def navigate(self, url, timeout=60):
        n = len(self.b.events)
        self.send("Page.navigate", {"url": url})
        deadline = time.time() + timeout
        while not any(e.get("method") == "Page.loadEventFired" and e.get("sessionId") == self.s
                      for e in self.b.events[n:]):
            if time.time() > deadline:
                raise CDPError("%s did not load" % url)
            self.b.poll_events(0.1)

    def eval(self, expr, timeout=60):
        r = self.send("Runtime.evaluate", {"expression": expr, "returnByValue": True, "awaitPromise": True},
                      timeout=timeout)
        if "exceptionDetails" in r:
            d = r["exceptionDetails"]
            raise CDPError("%s: %s" % (expr[:80], d.get("exception", {}).get("description", d.get("text"))))
        return r["result"].get("value")

    def wait_for(self, expr, timeout=30):
        deadline = time.time() + timeout
        while True:
            v = self.eval(expr)
            if v:
                return v
            if time.time() > deadline:
                raise CDPError("timed out waiting for %s" % expr)
            self.b.poll_events(0.05)

    def key(self, key, code=None, key_code=None, shift=False):
        base = {"key": key, "code": code or key, "windowsVirtualKeyCode": key_code or 0,
                "modifiers": 8 if shift else 0}
        self.send("Input.dispatchKeyEvent", dict(base, type="rawKeyDown"))
        self.send("Input.dispatchKeyEvent", dict(base, type="keyUp"))

    def click(self, x, y, shift=False):
        for t in ("mousePressed", "mouseReleased"):
            self.send("Input.dispatchMouseEvent", {"type": t, "x": x, "y": y, "button": "left", "clickCount": 1,
                                                   "modifiers": 8 if shift else 0})

    def screenshot(self, clip=None):
        """PNG bytes of the viewport, or of clip {x, y, width, height} (CSS pixels) at scale 1."""
        import base64
        params = {"format": "png"}
        if clip:
            params["clip"] = dict(clip, scale=1)
        return base64.b64decode(self.send("Page.captureScreenshot", params)["data"])
