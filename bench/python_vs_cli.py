"""The Python module against the command line on the same case, side by side: a run of the default
dam break (dx = 0.05 m, 23,236 particles, to t = 0.5 s, frames every 0.1 s) by `sluice run` and by
sluice.Simulation(...).run(), alternated ROUNDS times; the ratio of their stepping loops' times
(the summaries' "loop time"), that their last frames are bit for bit the same, and the module's import
time. Another build's program can be compared with SLUICE (its runs alternate with this build's).

    PYTHONPATH=build/release/python /usr/bin/python3 bench/python_vs_cli.py [ROUNDS] [THREADS]
"""
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

import sluice

rounds = int(sys.argv[1]) if len(sys.argv) > 1 else 3
threads = int(sys.argv[2]) if len(sys.argv) > 2 else 1
here = os.path.dirname(os.path.abspath(__file__))
program = os.environ.get("SLUICE", os.path.join(here, "..", "build", "release", "sluice"))
overrides = {"domain.dx": 0.05, "time.end": 0.5, "output.interval": 0.1}


def loop_seconds(summary):
    return float(re.search(r"loop time\s+([0-9.]+) s", summary).group(1))


cli, py = [], []
with tempfile.TemporaryDirectory() as work:
    for k in range(rounds):
        out_cli, out_py = f"{work}/cli{k}", f"{work}/py{k}"
        sets = [a for key, v in overrides.items() for a in ("--set", f"{key}={v}")]
        r = subprocess.run([program, "run", "dam_break", "-q", "--threads", str(threads), "-o", out_cli, *sets],
                           capture_output=True, text=True, check=True)
        cli.append(loop_seconds(r.stdout))
        sim = sluice.Simulation(sluice.load_case("dam_break", overrides=overrides), threads=threads,
                                output_dir=out_py)
        result = sim.run(progress=False)
        sim.close()
        py.append(result["loop_seconds"])
        a, b = sluice.open_run(out_cli).frames[-1], sluice.open_run(out_py).frames[-1]
        same = a["step"] == b["step"] and np.array_equal(a["x"], b["x"]) and np.array_equal(a["v"], b["v"])
        print(f"round {k + 1}: sluice run {cli[-1]:.3f} s, Python {py[-1]:.3f} s stepping; "
              f"last frames {'bit for bit the same' if same else 'DIFFER'} ({result['particles']} particles, "
              f"{a['step']} steps)")
        if not same:
            sys.exit("the Python run's particles differ from the command line's")

imports = []
for _ in range(5):
    code = "import time; t = time.perf_counter(); import sluice; print(time.perf_counter() - t)"
    imports.append(float(subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                                        check=True, env=os.environ).stdout))
print(f"{threads} thread(s), pair loop on {sluice.simd_target()}: Python / sluice run = "
      f"{statistics.median(py) / statistics.median(cli):.3f} (medians of {rounds}: {statistics.median(py):.3f} s "
      f"and {statistics.median(cli):.3f} s)")
print(f"import sluice: {min(imports) * 1e3:.0f} ms (the least of 5; median {statistics.median(imports) * 1e3:.0f} ms)")
