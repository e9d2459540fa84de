"""Screenshot a page in headless Chromium after a real-time wait.

`chromium --screenshot` fires on the load event plus a virtual-time budget, before
Foxglove has fetched and decoded the recording in its workers; this drives Chromium over
its DevTools pipe (`--remote-debugging-pipe`: fd 3 in, fd 4 out, NUL-separated JSON) to
wait in wall-clock seconds, with the standard library alone.
"""

import argparse
import base64
import json
import os
import subprocess
import time
from typing import Any

SOFTWARE_GL = ["--use-angle=swiftshader", "--enable-unsafe-swiftshader"]  # WebGL with no GPU


class DevTools:
    """Request/response over Chromium's DevTools pipe; events are read past and dropped."""

    def __init__(self, to_browser: int, from_browser: int) -> None:
        self.to_browser, self.from_browser, self.next_id, self.pending = to_browser, from_browser, 0, b""

    def call(self, method: str, session: str | None = None, **params: Any) -> dict[str, Any]:
        self.next_id += 1
        message = {"id": self.next_id, "method": method, "params": params}
        if session is not None:
            message["sessionId"] = session
        os.write(self.to_browser, json.dumps(message).encode() + b"\0")
        while True:
            while b"\0" not in self.pending:
                chunk = os.read(self.from_browser, 1 << 20)
                if not chunk:
                    raise RuntimeError(f"chromium closed its DevTools pipe during {method}")
                self.pending += chunk
            raw, self.pending = self.pending.split(b"\0", 1)
            reply = json.loads(raw)
            if reply.get("id") == self.next_id:
                if "error" in reply:
                    raise RuntimeError(f"{method}: {reply['error']}")
                return reply["result"]


def screenshot(url: str, out: str, wait: float, size: tuple[int, int], chromium: str) -> None:
    """Open `url` at `size`, wait `wait` seconds of wall-clock time, write the viewport as PNG."""
    to_browser_r, to_browser_w = os.pipe()
    from_browser_r, from_browser_w = os.pipe()

    def wire_pipes() -> None:  # in the child: fd 3 reads our commands, fd 4 writes its replies
        inbound, outbound = os.dup(to_browser_r), os.dup(from_browser_w)
        os.dup2(inbound, 3)
        os.dup2(outbound, 4)

    browser = subprocess.Popen(
        [chromium, "--headless", "--no-sandbox", "--hide-scrollbars", *SOFTWARE_GL,
         f"--window-size={size[0]},{size[1]}", "--remote-debugging-pipe", "about:blank"],
        preexec_fn=wire_pipes, close_fds=False, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    os.close(to_browser_r)
    os.close(from_browser_w)
    try:
        tools = DevTools(to_browser_w, from_browser_r)
        page = next(t for t in tools.call("Target.getTargets")["targetInfos"] if t["type"] == "page")
        session = tools.call("Target.attachToTarget", targetId=page["targetId"], flatten=True)["sessionId"]
        tools.call("Emulation.setDeviceMetricsOverride", session, width=size[0], height=size[1],
                   deviceScaleFactor=1, mobile=False)
        tools.call("Page.navigate", session, url=url)
        time.sleep(wait)
        png = tools.call("Page.captureScreenshot", session, format="png")["data"]
        with open(out, "wb") as file:
            file.write(base64.b64decode(png))
    finally:
        browser.terminate()
        browser.wait()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("url")
    parser.add_argument("out", help="PNG file to write")
    parser.add_argument("--wait", type=float, default=60.0, help="seconds between navigating and the picture")
    parser.add_argument("--size", default="1600x1000", help="window WIDTHxHEIGHT in pixels")
    parser.add_argument("--chromium", default="chromium")
    args = parser.parse_args()
    width, height = (int(v) for v in args.size.split("x"))
    screenshot(args.url, args.out, args.wait, (width, height), args.chromium)


if __name__ == "__main__":
    main()
