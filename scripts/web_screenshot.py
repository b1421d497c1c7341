"""Screenshot of the web page after "Try the example photo", with headless Chromium (docs/images/web-page.png).

Drives Chromium through the DevTools protocol over ``--remote-debugging-pipe`` (no extra Python packages).
Needs a Chromium binary (Debian: ``apt-get install chromium``).

Usage:
    PYTHONPATH=src python scripts/web_screenshot.py --out docs/images/web-page.png
    PYTHONPATH=src python scripts/web_screenshot.py --standins --out shot.png   # no model needed

``--standins`` serves the bundled example photo with a detector that returns its exact labels and the
nearest-pocket planner of ``pix2pockets.testing``, for builds without the detector model or planner.
"""

from __future__ import annotations

import argparse
import base64
import json
import os
import shutil
import subprocess
import sys
import threading
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def start_server(app, port: int):
    import uvicorn

    server = uvicorn.Server(uvicorn.Config(app, host="127.0.0.1", port=port, log_level="warning"))
    threading.Thread(target=server.run, daemon=True).start()
    t0 = time.time()
    while not server.started:
        if time.time() - t0 > 30:
            raise RuntimeError("the server did not start")
        time.sleep(0.1)
    return server


class Chromium:
    """Headless Chromium with DevTools commands over a pipe (fd 3 in, fd 4 out, NUL-separated JSON)."""

    def __init__(self, binary: str, width: int, height: int) -> None:
        cmd_r, self.cmd_w = os.pipe()
        self.res_r, res_w = os.pipe()

        def wire_pipes() -> None:  # runs in the child before exec
            a, b = os.dup(cmd_r), os.dup(res_w)
            os.dup2(a, 3)
            os.dup2(b, 4)
            os.set_inheritable(3, True)
            os.set_inheritable(4, True)

        args = [binary, "--headless=new", "--no-sandbox", "--disable-gpu", "--hide-scrollbars"]
        args += ["--remote-debugging-pipe", f"--window-size={width},{height}", "about:blank"]
        self.proc = subprocess.Popen(
            args, close_fds=False, preexec_fn=wire_pipes, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL
        )
        os.close(cmd_r)
        os.close(res_w)
        self.buf = b""
        self.last_id = 0
        self.attached: str | None = None  # the DevTools id of the page this browser drives

    def call(self, method: str, **params):
        self.last_id += 1
        msg = {"id": self.last_id, "method": method, "params": params}
        if self.attached and not method.startswith("Target."):
            msg["sessionId"] = self.attached
        os.write(self.cmd_w, json.dumps(msg).encode() + b"\0")
        while True:
            while b"\0" not in self.buf:
                chunk = os.read(self.res_r, 1 << 20)
                if not chunk:
                    raise RuntimeError("Chromium closed the DevTools pipe")
                self.buf += chunk
            raw, self.buf = self.buf.split(b"\0", 1)
            reply = json.loads(raw)
            if reply.get("id") == self.last_id:
                if "error" in reply:
                    raise RuntimeError(f"{method}: {reply['error']}")
                return reply["result"]

    def js(self, expression: str):
        return self.call("Runtime.evaluate", expression=expression, returnByValue=True)["result"].get("value")

    def close(self) -> None:
        self.proc.terminate()
        self.proc.wait(10)


def screenshot(app, out: str, binary: str, port: int, width: int, timeout: float) -> str:
    """Load the page, click "Try the example photo", wait for the answer and save a PNG; returns the answer."""
    server = start_server(app, port)
    browser = Chromium(binary, width, 1000)

    def resize(height: int) -> None:
        metrics = {"width": width, "height": height, "deviceScaleFactor": 1, "mobile": False}
        browser.call("Emulation.setDeviceMetricsOverride", **metrics)

    try:
        page = next(t for t in browser.call("Target.getTargets")["targetInfos"] if t["type"] == "page")
        browser.attached = browser.call("Target.attachToTarget", targetId=page["targetId"], flatten=True)["sessionId"]
        resize(1000)
        browser.call("Page.navigate", url=f"http://127.0.0.1:{port}/")
        t0 = time.time()
        while browser.js("document.readyState") != "complete":
            time.sleep(0.1)
        browser.js("document.getElementById('example').click()")
        while browser.js("document.getElementById('go').disabled || !document.getElementById('status').textContent"):
            if time.time() - t0 > timeout:
                raise RuntimeError("no answer in time")
            time.sleep(0.3)
        shown = "document.getElementById('result').hidden ? '' : document.getElementById('answer').textContent"
        answer = browser.js(shown)
        status = browser.js("document.getElementById('status').textContent")
        browser.js("document.querySelector('details').open = true")
        height = min(int(browser.js("document.documentElement.scrollHeight")), 1600)
        resize(height)
        time.sleep(0.3)
        Path(out).write_bytes(base64.b64decode(browser.call("Page.captureScreenshot", format="png")["data"]))
        return f"{status} {answer}".strip()
    finally:
        browser.close()
        server.should_exit = True


def standin_app():
    from pix2pockets.data.examples import example_photo_path
    from pix2pockets.testing import LabelsDetector, NearestPocketPlanner
    from pix2pockets.web.app import create_app

    photo = Path(example_photo_path())
    labels = json.loads(photo.with_name(photo.stem + ".labels.json").read_text())
    return create_app(LabelsDetector(labels), NearestPocketPlanner())


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default="docs/images/web-page.png")
    parser.add_argument("--standins", action="store_true", help="synthetic photo, exact labels, stand-in planner")
    parser.add_argument("--chromium", default=shutil.which("chromium") or "chromium")
    parser.add_argument("--port", type=int, default=8765)
    parser.add_argument("--width", type=int, default=1280)
    parser.add_argument("--timeout", type=float, default=180.0)
    args = parser.parse_args()
    if args.standins:
        app = standin_app()
    else:
        from pix2pockets.pipeline.photo import default_detector
        from pix2pockets.pipeline.planning import default_planner
        from pix2pockets.web.app import create_app

        app = create_app(default_detector(), default_planner())
    print(screenshot(app, args.out, args.chromium, args.port, args.width, args.timeout))
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
