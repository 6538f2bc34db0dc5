"""How fast the page of `sluice view` draws while the time slider is dragged over a run of about
100,000 particles (the default dam break at dx = 0.022 m, 109,435 particles, 11 frames), in real
time: headless Chromium driven over its DevTools protocol (--remote-debugging-pipe), the page's own
show(k) called frame after frame as the slider's input events call it, each frame followed by the
browser's next animation frame (so that it is composited). Two passes: the first fetches every frame
from the server (converted from its .npz at each request), the second draws them from the page's
cache. Frames per second is frames / wall time of the pass, the median of ROUNDS passes.

Chromium here draws with SwiftShader, WebGL on the CPU: a browser with a graphics card draws faster.

    /usr/bin/python3 bench/view_scrub.py [ROUNDS]     (after make build)
"""
import json
import os
import shutil
import socket
import statistics
import subprocess
import sys
import tempfile
import time

here = os.path.dirname(os.path.abspath(__file__))
sluice = os.environ.get("SLUICE", os.path.join(here, "..", "build", "release", "sluice"))
rounds = int(sys.argv[1]) if len(sys.argv) > 1 else 3


class DevTools:
    """Chromium's DevTools protocol over --remote-debugging-pipe: JSON messages ended by a NUL byte,
    commands written to the browser's fd 3 and answers read from its fd 4."""

    def __init__(self, url):
        to_browser_r, self.to_browser = os.pipe()
        self.from_browser, from_browser_w = os.pipe()
        self.profile = tempfile.mkdtemp(prefix="sluice_scrub_profile_")
        cmd = ["chromium", "--headless", "--no-sandbox", "--use-gl=swiftshader", "--enable-unsafe-swiftshader",
               "--window-size=1300,800", "--hide-scrollbars", "--remote-debugging-pipe",
               f"--user-data-dir={self.profile}", "about:blank"]

        def fds():
            os.dup2(to_browser_r, 3)
            os.dup2(from_browser_w, 4)

        self.browser = subprocess.Popen(cmd, pass_fds=(3, 4), preexec_fn=fds, stdout=subprocess.DEVNULL,
                                        stderr=subprocess.DEVNULL)
        os.close(to_browser_r)
        os.close(from_browser_w)
        self.next_id = 0
        self.buffer = b""
        target = self.call("Target.createTarget", {"url": url})["targetId"]
        self.session = self.call("Target.attachToTarget", {"targetId": target, "flatten": True})["sessionId"]

    def call(self, method, params=None, session=None):
        self.next_id += 1
        message = {"id": self.next_id, "method": method, "params": params or {}}
        if session:
            message["sessionId"] = session
        os.write(self.to_browser, json.dumps(message).encode() + b"\0")
        while True:
            while b"\0" not in self.buffer:
                chunk = os.read(self.from_browser, 1 << 16)
                if not chunk:
                    raise RuntimeError("chromium closed its DevTools pipe")
                self.buffer += chunk
            raw, self.buffer = self.buffer.split(b"\0", 1)
            answer = json.loads(raw)
            if answer.get("id") == self.next_id:
                if "error" in answer:
                    raise RuntimeError(f"{method}: {answer['error']}")
                return answer["result"]

    def evaluate(self, expression):
        result = self.call("Runtime.evaluate", {"expression": expression, "awaitPromise": True,
                                                "returnByValue": True}, self.session)
        if "exceptionDetails" in result:
            raise RuntimeError(f"the page threw: {result['exceptionDetails']}")
        return result["result"].get("value")

    def close(self):
        self.browser.kill()
        self.browser.wait()
        shutil.rmtree(self.profile, ignore_errors=True)


# One pass over every frame: show(k) as the slider calls it, then the browser's next animation frame.
SCRUB = """(async () => {
  const next = () => new Promise((r) => requestAnimationFrame(() => r()));
  const t0 = performance.now();
  for (let k = 0; k < state.frames.length; k++) { await show(k); await next(); }
  return { frames: state.frames.length, seconds: (performance.now() - t0) / 1000, n: state.shown.n };
})()"""


def main():
    work = tempfile.mkdtemp(prefix="sluice_scrub_")
    run_dir = os.path.join(work, "run")
    subprocess.run([sluice, "run", "dam_break", "-q", "-o", run_dir, "--set", "domain.dx=0.022", "--set",
                    "time.end=0.1", "--set", "output.interval=0.01"], check=True, stdout=subprocess.DEVNULL)
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    server = subprocess.Popen([sluice, "view", run_dir, "--port", str(port)], stderr=subprocess.PIPE, text=True)
    server.stderr.readline()
    cold, warm = [], []
    try:
        for _ in range(rounds):
            browser = DevTools(f"http://127.0.0.1:{port}/")
            try:
                for _ in range(600):  # the page's first frame drawn
                    if browser.evaluate("typeof state !== 'undefined' && state.shown !== null && state.drawn > 0"):
                        break
                    time.sleep(0.05)
                first = browser.evaluate(SCRUB)
                second = browser.evaluate(SCRUB)
            finally:
                browser.close()
            cold.append(first["frames"] / first["seconds"])
            warm.append(second["frames"] / second["seconds"])
            print(f"{first['n']} particles, {first['frames']} frames: {cold[-1]:.1f} frames/s fetched from the "
                  f"server, {warm[-1]:.1f} frames/s from the page's cache", flush=True)
    finally:
        server.terminate()
        server.wait()
        shutil.rmtree(work, ignore_errors=True)
    cpu = subprocess.run(["sh", "-c", "grep -m1 'model name' /proc/cpuinfo | cut -d: -f2"], capture_output=True,
                         text=True).stdout.strip()
    print(f"scrubbing, median of {rounds}: {statistics.median(cold):.1f} frames/s fetched, "
          f"{statistics.median(warm):.1f} frames/s cached ({cpu}; Chromium with SwiftShader, WebGL on the CPU)")


main()
