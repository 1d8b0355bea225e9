"""A headless Chromium driven over the DevTools protocol's pipe: how the tests and benchmarks
open an exported page in a real browser (issue 17). No bpy, no dependency.

Chromium reads protocol commands from its file descriptor 3 and writes answers to 4, each a
JSON text ended by NUL (`--remote-debugging-pipe`): no socket, no port. WebGL2 comes from
SwiftShader, the software renderer Chromium ships (ANGLE), so a machine without a GPU
renders the page too.

    with Chromium() as browser:                       # doctest: +SKIP
        page = browser.open("file:///tmp/painting.html", 800, 600)
        page.evaluate("document.title")
"""
import base64
import fcntl
import json
import os
import shutil
import subprocess
import tempfile

NAMES = ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable", "chrome")
SOFTWARE_GL = ("--use-angle=swiftshader", "--enable-unsafe-swiftshader")
FLAGS = ("--headless", "--remote-debugging-pipe", "--ignore-gpu-blocklist", "--no-first-run",
         "--no-default-browser-check", "--disable-extensions", "--mute-audio",
         "--allow-file-access-from-files", "--disable-background-timer-throttling",
         "--disable-renderer-backgrounding", "--disable-backgrounding-occluded-windows")


class BrowserError(RuntimeError):
    pass


def find_chromium():
    """The Chromium executable: $DYNPAINT_CHROMIUM, else the first of NAMES on PATH, else None."""
    exe = os.environ.get("DYNPAINT_CHROMIUM")
    if exe:
        return exe if os.path.isfile(exe) else None
    return next((path for path in map(shutil.which, NAMES) if path), None)


class Chromium:
    """One headless browser process; `open` gives a Page (a tab attached over the pipe).
    gpu: let it use the machine's GPU (else SwiftShader, the same pixels on every machine)."""

    def __init__(self, executable=None, extra_flags=(), gpu=False):
        exe = executable or find_chromium()
        if exe is None:
            raise BrowserError("no Chromium found: install Debian's `chromium` package or set "
                               "DYNPAINT_CHROMIUM to the browser's executable")
        self.profile = tempfile.mkdtemp(prefix="dynpaint-chromium-")
        cmd_read, self._cmd = os.pipe()       # we write commands, Chromium reads fd 3
        self._answers, answer_write = os.pipe()

        def child_fds():
            high = [fcntl.fcntl(fd, fcntl.F_DUPFD, 10) for fd in (cmd_read, answer_write)]
            os.dup2(high[0], 3)
            os.dup2(high[1], 4)

        flags = [*FLAGS, *(() if gpu else SOFTWARE_GL), *extra_flags]
        flags += ["--no-sandbox"] if os.geteuid() == 0 else []
        self.proc = subprocess.Popen(
            [exe, *flags, f"--user-data-dir={self.profile}", "about:blank"],
            stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
            preexec_fn=child_fds, pass_fds=(3, 4))
        os.close(cmd_read)
        os.close(answer_write)
        self._buffer = b""
        self._next_id = 0
        self.events = []

    def send(self, method, params=None, session=None):
        """Send one command and wait for its answer → its result (dict)."""
        self._next_id += 1
        message = {"id": self._next_id, "method": method, "params": params or {}}
        if session:
            message["sessionId"] = session
        os.write(self._cmd, json.dumps(message).encode() + b"\0")
        while True:
            answer = self._read()
            if answer.get("id") == self._next_id:
                if "error" in answer:
                    raise BrowserError(f"{method}: {answer['error'].get('message')}")
                return answer.get("result", {})
            self.events.append(answer)

    def _read(self):
        while b"\0" not in self._buffer:
            chunk = os.read(self._answers, 1 << 20)
            if not chunk:
                raise BrowserError("Chromium closed its DevTools pipe (did it start?)")
            self._buffer += chunk
        text, self._buffer = self._buffer.split(b"\0", 1)
        return json.loads(text)

    def open(self, url, width=800, height=600, scale=1.0):
        """A new tab of `width` × `height` CSS pixels at device pixel ratio `scale`, loaded."""
        target = self.send("Target.createTarget", {"url": "about:blank"})["targetId"]
        session = self.send("Target.attachToTarget", {"targetId": target,
                                                      "flatten": True})["sessionId"]
        page = Page(self, session)
        page.send("Emulation.setDeviceMetricsOverride", {
            "width": width, "height": height, "deviceScaleFactor": scale, "mobile": False})
        page.send("Page.enable")
        page.send("Page.navigate", {"url": url})
        page.wait_for("document.readyState === 'complete'")
        return page

    def close(self):
        if self.proc.poll() is None:
            try:
                self.send("Browser.close")
            except (BrowserError, OSError):
                pass
            try:
                self.proc.wait(10)
            except subprocess.TimeoutExpired:
                self.proc.kill()
        for fd in (self._cmd, self._answers):
            try:
                os.close(fd)
            except OSError:
                pass
        shutil.rmtree(self.profile, ignore_errors=True)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


class Page:
    """One tab: evaluate scripts (awaiting promises) and send input events."""

    def __init__(self, browser, session):
        self.browser = browser
        self.session = session

    def send(self, method, params=None):
        return self.browser.send(method, params, self.session)

    def evaluate(self, expression):
        """The value of a JavaScript expression (a promise is awaited), as JSON data."""
        result = self.send("Runtime.evaluate", {"expression": expression, "awaitPromise": True,
                                                "returnByValue": True})
        if "exceptionDetails" in result:
            details = result["exceptionDetails"]
            text = details.get("exception", {}).get("description") or details.get("text")
            raise BrowserError(f"script failed: {text}")
        return result["result"].get("value")

    def wait_for(self, condition, timeout_s=60):
        """Wait until the JavaScript `condition` is true (polled in the page)."""
        ok = self.evaluate(f"""new Promise(done => {{
            const start = performance.now();
            (function poll() {{
                if ({condition}) return done(true);
                if (performance.now() - start > {timeout_s * 1000}) return done(false);
                setTimeout(poll, 20);
            }})();
        }})""")
        if not ok:
            raise BrowserError(f"timed out waiting for {condition}")

    def box(self, element_id):
        """[left, top, width, height] of the element `element_id`, in CSS pixels."""
        return self.evaluate(f"(() => {{ const r = document.getElementById('{element_id}')"
                             ".getBoundingClientRect(); return [r.left, r.top, r.width, "
                             "r.height]; })()")

    def screenshot(self, path):
        """Save what the tab shows as a PNG."""
        data = self.send("Page.captureScreenshot", {"format": "png"})["data"]
        with open(path, "wb") as fh:
            fh.write(base64.b64decode(data))

    def mouse(self, kind, x, y, buttons=1):
        """A mouse event at CSS pixel (x, y): kind pressed, moved or released."""
        self.send("Input.dispatchMouseEvent", {
            "type": {"pressed": "mousePressed", "moved": "mouseMoved",
                     "released": "mouseReleased"}[kind],
            "x": x, "y": y, "button": "left", "buttons": buttons if kind != "released" else 0,
            "clickCount": 1})

    def wheel(self, x, y, delta_y):
        """A wheel turn over CSS pixel (x, y): positive delta_y scrolls down."""
        self.send("Input.dispatchMouseEvent", {"type": "mouseWheel", "x": x, "y": y,
                                               "deltaX": 0, "deltaY": delta_y})

    def touch(self, kind, x, y):
        """A one-finger touch at CSS pixel (x, y): kind start, move or end."""
        self.send("Input.dispatchTouchEvent", {
            "type": {"start": "touchStart", "move": "touchMove", "end": "touchEnd"}[kind],
            "touchPoints": [] if kind == "end" else [{"x": x, "y": y}]})

    def key(self, key, code=None):
        """Press and release one key (e.g. 'ArrowLeft', ' ')."""
        for kind in ("keyDown", "keyUp"):
            self.send("Input.dispatchKeyEvent", {"type": kind, "key": key,
                                                 "code": code or key, "windowsVirtualKeyCode":
                                                 KEY_CODES.get(key, 0)})


KEY_CODES = {"ArrowLeft": 37, "ArrowUp": 38, "ArrowRight": 39, "ArrowDown": 40, " ": 32,
             "Home": 36, "PageUp": 33, "PageDown": 34, "r": 82, "Enter": 13}
