"""The speed of `sluice view`, two figures:

1. a frame of about 100,000 particles (the default dam break at dx = 0.022 m, 109,435 particles)
   from the server: the time of GET /api/frame/k, request to last byte, median of 30;
2. a live view's cost to the run: `sluice run` of the default dam break (dx = 0.05 m, 23,236
   particles, to t = 1 s, a frame every 0.02 s) with and without --view, the --view runs with a
   client that asks what the open page asks (the run, series and diagnostics every second and each
   new frame), alternated ROUNDS times; the ratio of the stepping loops' medians.

    /usr/bin/python3 bench/view_speed.py [ROUNDS]     (after make build)
"""
import json
import os
import re
import statistics
import subprocess
import sys
import tempfile
import threading
import time
import urllib.request

here = os.path.dirname(os.path.abspath(__file__))
sluice = os.environ.get("SLUICE", os.path.join(here, "..", "build", "release", "sluice"))
rounds = int(sys.argv[1]) if len(sys.argv) > 1 else 3


def get(url):
    with urllib.request.urlopen(url, timeout=30) as r:
        return r.read()


def loop_seconds(summary):
    return float(re.search(r"loop time\s+([0-9.]+) s", summary).group(1))


with tempfile.TemporaryDirectory() as work:
    big = os.path.join(work, "big")
    subprocess.run([sluice, "run", "dam_break", "-q", "--threads", "2", "-o", big, "--set", "domain.dx=0.022",
                    "--set", "time.end=0.004", "--set", "output.interval=0.001"], check=True, capture_output=True)
    server = subprocess.Popen([sluice, "view", big, "--port", "0"], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                              text=True)
    address = re.search(r"(http://\S+)", server.stderr.readline()).group(1)
    frames = json.loads(get(address + "api/run"))["frames"]
    times = []
    for k in range(30):
        t = time.perf_counter()
        body = get(address + f"api/frame/{frames[k % len(frames)]['index']}?field=speed")
        times.append(time.perf_counter() - t)
    header = json.loads(body[4:4 + int.from_bytes(body[:4], "little")])
    print(f"1. a frame of {header['n']} particles ({len(body) / 1e6:.2f} MB) from the server: median "
          f"{statistics.median(times) * 1e3:.1f} ms, slowest {max(times) * 1e3:.1f} ms of 30")
    server.terminate()
    server.wait()

    plain, viewed = [], []
    case = ["dam_break", "-q", "--threads", "1", "--set", "domain.dx=0.05", "--set", "time.end=1",
            "--set", "output.interval=0.02"]
    for k in range(rounds):
        out = os.path.join(work, f"plain{k}")
        plain.append(loop_seconds(subprocess.run([sluice, "run", *case, "-o", out], capture_output=True, text=True,
                                                 check=True).stdout))
        out = os.path.join(work, f"viewed{k}")
        run = subprocess.Popen([sluice, "run", *case, "-o", out, "--view", "--port", "0"], stdout=subprocess.PIPE,
                               stderr=subprocess.PIPE, text=True)
        address = re.search(r"(http://\S+)", run.stderr.readline()).group(1).split("?")[0]
        done = threading.Event()

        def page():  # what the open page asks for
            seen = -1
            while not done.is_set():
                try:
                    listed = json.loads(get(address + "api/run"))["frames"]
                    get(address + "api/series")
                    get(address + "api/diagnostics")
                    if listed and listed[-1]["index"] != seen:
                        seen = listed[-1]["index"]
                        get(address + f"api/frame/{seen}?field=speed")
                except OSError:
                    pass
                done.wait(1.0)

        client = threading.Thread(target=page)
        client.start()
        stdout, _ = run.communicate()
        done.set()
        client.join()
        viewed.append(loop_seconds(stdout))
        print(f"   round {k + 1}: sluice run {plain[-1]:.3f} s, with --view and a page open {viewed[-1]:.3f} s")
    print(f"2. a live view's cost: with / without = {statistics.median(viewed) / statistics.median(plain):.3f} "
          f"(medians of {rounds}: {statistics.median(viewed):.3f} s and {statistics.median(plain):.3f} s)")
