#!/usr/bin/python3
"""The parameter fuzzer: runs the built-in cases for a few steps with case keys set to the ends of
their documented ranges and to random values inside them (one key at a time, and several at once),
and checks that every run ends as sluice promises: exit status 0, 1 or 2, with a `sluice: error:`
message for 1 and 2 -- never a signal (a crash), a hang, or a failure without a message.

The keys, their types and ranges come from `sluice keys --json` (the parameter table), the cases from
`sluice cases`. A run that is still going after --timeout seconds is sent SIGINT and must then stop
with status 130; one that does not within 60 s more is a hang. Each run's address space is limited
(--memory-gb), so that a setting which would take more memory than the machine has ends in sluice's
out-of-memory message instead of the kernel's out-of-memory killer.

    tests/param_fuzz.py --sluice build/release/sluice --workdir /tmp/fuzz --runs 2000 --seed 1
    tests/param_fuzz.py ... --runs 0    # every key of every case three times (ends and inside)

`make test` runs a short version (ctest: param_fuzz_short)."""

import argparse
import json
import math
import os
import random
import re
import resource
import shutil
import signal
import subprocess
import sys
import time

parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
parser.add_argument("--sluice", required=True)
parser.add_argument("--workdir", required=True)
parser.add_argument("--runs", type=int, default=40, help="random runs; 0 = every key of every case three times")
parser.add_argument("--seed", type=int, default=None)
parser.add_argument("--timeout", type=float, default=60.0, help="seconds before a run is sent SIGINT")
parser.add_argument("--memory-gb", type=float, default=6.0, help="address-space limit per run")
parser.add_argument("--end", type=float, default=0.005, help="time.end of each run (a few steps)")
args = parser.parse_args()

seed = args.seed if args.seed is not None else random.randrange(1 << 30)
rng = random.Random(seed)
print(f"param_fuzz: seed {seed} (--seed to repeat)", flush=True)
shutil.rmtree(args.workdir, ignore_errors=True)
os.makedirs(args.workdir)

KEYS = json.loads(subprocess.run([args.sluice, "keys", "--json"], capture_output=True, text=True, check=True).stdout)
CASES = [line.split()[0] for line in subprocess.run([args.sluice, "cases"], capture_output=True, text=True,
                                                    check=True).stdout.splitlines() if line.strip()]


def case_facts(name):
    """The case's dimension and how many [[water]], [[wall]], [[probe]] items it has."""
    path = os.path.join(args.workdir, f"{name}.toml")
    subprocess.run([args.sluice, "init", path, "--from", name, "--force"], capture_output=True, check=True)
    text = open(path).read()
    dimension = int(re.search(r"^dimension = (\d)", text, re.M).group(1))
    items = {s: len(re.findall(rf"^\[\[{s}\]\]", text, re.M)) for s in ("water", "wall", "probe")}
    return dimension, items


FACTS = {name: case_facts(name) for name in CASES}
EXTREMES = [0.0, -0.0, 1e-300, -1e-300, 1e-9, -1.0, 1.0, 1e9, -1e9, 1e300, -1e300]


def number(key, low=None, high=None, integer=False):
    """A value at an end of [low, high] or inside it; anything from EXTREMES when unbounded."""
    if low is None or high is None:
        return rng.choice(EXTREMES + [rng.gauss(0.0, 10.0), rng.uniform(-1.0, 1.0)])
    pick = rng.random()
    if pick < 0.25:
        v = low
    elif pick < 0.5:
        v = min(high, 1e6 if high > 1e6 else high)  # the upper end (a finite stand-in for "no limit")
    elif low > 0.0 and high / low > 100.0:
        v = math.exp(rng.uniform(math.log(low), math.log(min(high, 1e6))))
    else:
        v = rng.uniform(low, min(high, 1e6))
    return int(round(v)) if integer else v


def toml_number(v):
    if isinstance(v, int):
        return str(v)
    text = repr(float(v))
    return text if any(c in text for c in ".en") else text + ".0"


def value_for(k, dimension):
    t = k["type"]
    low, high = k.get("lower"), k.get("upper")
    if t == "number":
        return toml_number(number(k["key"], low, high))
    if t == "integer":
        return toml_number(number(k["key"], low, high, integer=True))
    if t == "boolean":
        return rng.choice(["true", "false"])
    if t == "choice":
        return '"' + rng.choice(k["choices"]) + '"'
    if t == "vector":
        return "[" + ", ".join(toml_number(number(k["key"])) if rng.random() < 0.3 else toml_number(rng.uniform(-1, 5))
                               for _ in range(dimension)) + "]"
    if t == "points":
        n = rng.randint(3, 6)
        return "[" + ", ".join(f"[{toml_number(rng.uniform(-1, 5))}, {toml_number(rng.uniform(-1, 5))}]"
                               for _ in range(n)) + "]"
    if t == "string":
        return '"' + rng.choice(["x", "a" * rng.randint(1, 300), "out put", "ü", ""]) + '"'
    return None  # lists of strings: left to the case-file fuzzer


def target(k, items):
    """The key as --set writes it: "water[1].min" for an item's key (a random item of the case)."""
    if not k["item"]:
        return k["key"]
    count = items.get(k["section"], 0)
    if count == 0:
        return None
    return f"{k['section']}[{rng.randrange(count)}].{k['key'].split('.', 1)[1]}"


def assignments(case, k):
    dimension, items = FACTS[case]
    if k["only_3d"] and dimension != 3:
        return None
    key = target(k, items)
    value = value_for(k, dimension)
    return None if key is None or value is None else f"{key}={value}"


counts = {}
failures = []
run_index = 0


def run_one(case, sets):
    global run_index
    run_index += 1
    out = os.path.join(args.workdir, f"run_{run_index % 4}")
    shutil.rmtree(out, ignore_errors=True)
    command = [args.sluice, "run", case, "-q", "--threads", "1", "-o", out, "--set", f"time.end={args.end}"]
    for s in sets:
        command += ["--set", s]

    def limit():
        size = int(args.memory_gb * (1 << 30))
        resource.setrlimit(resource.RLIMIT_AS, (size, size))

    p = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, preexec_fn=limit)
    interrupted = False
    try:
        stdout, stderr = p.communicate(timeout=args.timeout)
    except subprocess.TimeoutExpired:
        interrupted = True
        p.send_signal(signal.SIGINT)
        try:
            stdout, stderr = p.communicate(timeout=60)
        except subprocess.TimeoutExpired:
            p.kill()
            stdout, stderr = p.communicate()
            failures.append((command, "hang: still running 60 s after SIGINT", stderr[-2000:]))
            counts["hang"] = counts.get("hang", 0) + 1
            return
    status = p.returncode
    counts[status] = counts.get(status, 0) + 1
    if interrupted:
        print(f"  (interrupted after {args.timeout:g} s, status {status}: {' '.join(sets)} on {case})", flush=True)
    shown = " ".join(command)
    if status < 0:
        failures.append((shown, f"killed by signal {-status} ({signal.Signals(-status).name})", stderr[-2000:]))
    elif status == 130 and not interrupted:
        failures.append((shown, "status 130 without an interrupt", stderr[-2000:]))
    elif status in (1, 2) and "sluice: error: " not in stderr:
        failures.append((shown, f"status {status} without a 'sluice: error:' message", stderr[-2000:]))
    elif status not in (0, 1, 2, 130):
        failures.append((shown, f"unexpected status {status}", stderr[-2000:]))


start = time.time()
numeric_first = sorted(KEYS, key=lambda k: k["type"] not in ("number", "integer"))
if args.runs == 0:
    for case in CASES:
        for k in numeric_first:
            for _ in range(3):
                a = assignments(case, k)
                if a is not None:
                    run_one(case, [a])
else:
    for _ in range(args.runs):
        case = rng.choice(CASES)
        # Mostly one key; every fourth run three at once (settings that only fail together).
        chosen = [rng.choice(KEYS) for _ in range(3 if rng.random() < 0.25 else 1)]
        sets = [a for a in (assignments(case, k) for k in chosen) if a is not None]
        if sets:
            run_one(case, sets)

total = sum(counts.values())
summary = ", ".join(f"exit {k}: {v}" for k, v in sorted(counts.items(), key=lambda kv: str(kv[0])))
print(f"param_fuzz: {total} runs in {time.time() - start:.0f} s ({summary}); {len(failures)} failures", flush=True)
for command, what, stderr in failures[:20]:
    print(f"FAIL {what}\n  {command}\n  {stderr.strip()[-600:]}", flush=True)
print(f"{total - len(failures)} passed, {len(failures)} failed")
sys.exit(1 if failures else 0)
