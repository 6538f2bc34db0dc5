"""The page of `sluice view` in headless Chromium (Debian chromium, software WebGL): a finished 2D and
3D run drawn (the canvas not blank, the time label that of the frame shown), a live run followed and
controlled from its page, and the command's bad input. Screenshots are left in the work directory to
be looked at.

    test_page.py --sluice build/release/sluice --workdir DIR
"""
import argparse
import json
import os
import re
import shutil
import signal
import socket
import subprocess
import sys
import time
import urllib.request

parser = argparse.ArgumentParser()
parser.add_argument("--sluice", required=True)
parser.add_argument("--workdir", required=True)
args = parser.parse_args()
work = args.workdir
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
failures = []


def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what, flush=True)
    if not ok:
        failures.append(what)


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def chromium(url, screenshot=None, budget=15000):
    """The page's status line (JSON) after it has loaded and drawn, and a screenshot."""
    base = ["chromium", "--headless", "--no-sandbox", "--use-gl=swiftshader", "--enable-unsafe-swiftshader",
            "--window-size=1300,800", f"--virtual-time-budget={budget}", "--hide-scrollbars"]
    if screenshot:
        subprocess.run(base + [f"--screenshot={screenshot}", url], capture_output=True, timeout=120)
    dom = subprocess.run(base + ["--dump-dom", url], capture_output=True, text=True, timeout=120).stdout
    m = re.search(r'<pre id="status"[^>]*>(.*?)</pre>', dom, re.S)
    return json.loads(m.group(1).replace("&quot;", '"').replace("&amp;", "&")) if m and m.group(1) else {}


def serve(run_dir, port):
    p = subprocess.Popen([args.sluice, "view", run_dir, "--port", str(port)], stderr=subprocess.PIPE, text=True)
    line = p.stderr.readline()
    check(f"http://127.0.0.1:{port}/" in line, f"sluice view prints its address: {line.strip()}")
    return p


def run(case, out, *sets):
    cmd = [args.sluice, "run", case, "-q", "--threads", "1", "-o", out]
    for s in sets:
        cmd += ["--set", s]
    subprocess.run(cmd, check=True, capture_output=True)


def frame_times(run_dir):
    with open(os.path.join(run_dir, "diagnostics.csv")) as f:
        return [float(line.split(",")[0]) for line in f.readlines()[1:]]


# A finished 2D run and a finished 3D run.
for name, case, sets in [("2d", "dam_break", ["domain.dx=0.2", "time.end=1"]),
                         ("3d", "dam_break_3d", ["domain.dx=0.04", "time.end=0.3", "output.interval=0.1"])]:
    out = os.path.join(work, name)
    run(case, out, *sets)
    port = free_port()
    server = serve(out, port)
    status = chromium(f"http://127.0.0.1:{port}/", os.path.join(work, f"{name}.png"))
    times = frame_times(out)
    check(status.get("frame") == len(times) - 1, f"{name}: the newest frame is shown ({status.get('frame')})")
    check(status.get("dimension") == (3 if name == "3d" else 2), f"{name}: drawn in {status.get('dimension')}D")
    check(f"t = {times[-1]:.3f} s" in status.get("label", ""), f"{name}: the label has the frame's time: "
          f"{status.get('label')}")
    check(status.get("coloured", 0) > 500, f"{name}: the canvas is drawn on ({status.get('coloured')} samples)")
    check(status.get("water", 0) > 100, f"{name}: the water is drawn in colour ({status.get('water')} samples)")
    check(status.get("message") == "", f"{name}: no error shown ({status.get('message')})")
    if name == "2d":
        # A second server on the same port is refused; so is a directory that is not a run.
        second = subprocess.run([args.sluice, "view", out, "--port", str(port)], capture_output=True, text=True,
                                timeout=30)
        check(second.returncode == 2 and "in use" in second.stderr, f"a port in use: {second.stderr.strip()}")
    server.send_signal(signal.SIGINT)
    check(server.wait(timeout=30) == 0, f"{name}: Ctrl-C stops the server cleanly")

# A validation case: the experiment's data drawn over its probe, in the run's units.
out = os.path.join(work, "buchner")
run("buchner", out, "domain.dx=0.03", "time.end=1.2")
port = free_port()
server = serve(out, port)
with urllib.request.urlopen(f"http://127.0.0.1:{port}/api/series") as r:
    references = {ref["series"]: ref for ref in json.load(r).get("references", [])}
wall = references.get("wall_pressure", {})
check(wall.get("label") == "Buchner (2002)" and len(wall.get("t", [])) > 30 and max(wall.get("value", [0])) > 1000,
      f"buchner: the experiment's wall pressure is served with the series, in pascals "
      f"({len(wall.get('t', []))} points, largest {max(wall.get('value', [0])):.0f} Pa)")
status = chromium(f"http://127.0.0.1:{port}/", os.path.join(work, "buchner.png"))
check(status.get("references") == 1, f"buchner: the page draws it over the probe ({status.get('references')} plot)")
server.send_signal(signal.SIGINT)
check(server.wait(timeout=30) == 0, "buchner: Ctrl-C stops the server cleanly")

bad = subprocess.run([args.sluice, "view", work], capture_output=True, text=True)
check(bad.returncode == 2 and "not a sluice run" in bad.stderr, f"not a run: {bad.stderr.strip()}")
bad = subprocess.run([args.sluice, "view", os.path.join(work, "nothing")], capture_output=True, text=True)
check(bad.returncode == 2 and "no such run directory" in bad.stderr, f"no directory: {bad.stderr.strip()}")

def frames_on_disk(run_dir):
    frames = os.path.join(run_dir, "frames")
    return len([f for f in os.listdir(frames) if f.endswith(".npz")]) if os.path.isdir(frames) else 0


def wait_for_frames(run_dir, more_than, seconds=60):
    """Waits until the run has written more than `more_than` frames (a sanitizer build steps slowly)."""
    deadline = time.time() + seconds
    while frames_on_disk(run_dir) <= more_than and time.time() < deadline:
        time.sleep(0.2)


# A live run: the page follows it, and its controls pause, resume and stop it.
port = free_port()
live_dir = os.path.join(work, "live")
live = subprocess.Popen([args.sluice, "run", "dam_break", "-o", live_dir, "--threads", "1", "--view", "--port",
                         str(port), "--set", "domain.dx=0.05", "--set", "time.end=60", "--set", "output.interval=0.02",
                         "-q"],
                        stderr=subprocess.PIPE, text=True)
address = ""
while not address:
    line = live.stderr.readline()
    if not line:
        break
    m = re.search(r"(http://127\.0\.0\.1:\d+/\?token=[0-9a-f]{32})", line)
    address = m.group(1) if m else ""
check(bool(address), f"sluice run --view prints the address with its token: {address}")
token = address.split("token=")[1]
wait_for_frames(live_dir, 3)
first = chromium(f"http://127.0.0.1:{port}/", os.path.join(work, "live.png"), budget=4000)
wait_for_frames(live_dir, frames_on_disk(live_dir) + 2)
second = chromium(f"http://127.0.0.1:{port}/", budget=4000)
check(first.get("frame") is not None and second.get("frame", -1) > first.get("frame"),
      f"the live page follows the run: frame {first.get('frame')}, then {second.get('frame')}")


def api(path, post=False):
    request = urllib.request.Request(f"http://127.0.0.1:{port}{path}", data=b"" if post else None,
                                     method="POST" if post else "GET")
    try:
        with urllib.request.urlopen(request, timeout=10) as r:
            return r.status, json.loads(r.read())
    except urllib.error.HTTPError as e:
        return e.code, json.loads(e.read())


check(api("/api/control/pause", post=True)[0] == 403, "the controls need the token")
check(api(f"/api/control/pause?token={token}", post=True)[0] == 200, "pause")
time.sleep(1.0)
before = len(api("/api/run")[1]["frames"])
time.sleep(2.0)
paused = api("/api/run")[1]
check(len(paused["frames"]) == before and paused["paused"], f"paused: {before} frames, then {len(paused['frames'])}")
checkpoint = os.path.join(live_dir, "checkpoint.bin")
written = os.stat(checkpoint).st_mtime_ns if os.path.exists(checkpoint) else 0
check(api(f"/api/control/checkpoint?token={token}", post=True)[0] == 200, "checkpoint now")
time.sleep(1.0)
check(os.path.exists(checkpoint) and os.stat(checkpoint).st_mtime_ns > written, "a checkpoint written while paused")
check(api(f"/api/control/resume?token={token}", post=True)[0] == 200, "resume")
wait_for_frames(live_dir, before)
check(len(api("/api/run")[1]["frames"]) > before, "running again after resume")
check(api(f"/api/control/stop?token={token}", post=True)[0] == 200, "stop")
status = live.wait(timeout=60)
check(status == 130, f"the run stops as Ctrl-C stops it (exit status {status})")
with open(os.path.join(live_dir, "summary.txt")) as f:
    check("stopped on request" in f.read(), "its summary says it was stopped")

print(f"{len(failures)} failure(s); screenshots in {work}")
sys.exit(1 if failures else 0)
