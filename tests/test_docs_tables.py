#!/usr/bin/env python3
"""docs/gen_tables.py, which turns a `sluice validate` directory into the docs' validation tables:
run on a real (quick, one-case) validate run, every row of validation.csv and checks.csv becomes a
table row with its numbers, the variant's RMS in its own column, and the command and program named."""
import argparse
import csv
import subprocess
import sys
import tempfile
from pathlib import Path

parser = argparse.ArgumentParser()
parser.add_argument("--sluice", required=True)
args = parser.parse_args()
generator = Path(__file__).resolve().parent.parent / "docs" / "gen_tables.py"

with tempfile.TemporaryDirectory() as tmp:
    out = Path(tmp) / "v"
    run = subprocess.run([args.sluice, "validate", "--quick", "--case", "koshizuka_oka", "--threads", "1", "-q",
                          "-o", str(out)], capture_output=True, text=True)
    if run.returncode not in (0, 1):
        sys.exit(f"sluice validate failed ({run.returncode}):\n{run.stderr}")
    table = subprocess.run(["/usr/bin/python3", str(generator), "validation", str(out), "sluice validate --quick",
                            "12", args.sluice], capture_output=True, text=True, check=True).stdout
    rows = list(csv.DictReader(open(out / "validation.csv", newline="")))
    checks = list(csv.DictReader(open(out / "checks.csv", newline="")))
    failures = []
    if "`sluice validate --quick`: 12 s wall on" not in table or "pair loop:" not in table:
        failures.append("the first line does not name the command, its time and the program")
    if "| RMS, `dynamic` |" not in table:
        failures.append("no column for the dynamic walls' variant")
    lines = table.splitlines()
    for r in rows:
        if r["variant"]:
            continue
        line = [l for l in lines if l.startswith(f"| {r['case']} | {r['quantity']} | {r['window']} | {r['points']} |")]
        if len(line) != 1:
            failures.append(f"row {r['case']} {r['comparison']}: {len(line)} table lines")
            continue
        dynamic = [o for o in rows if o["variant"] == "dynamic" and o["comparison"] == r["comparison"]]
        want = f"| {float(r['rms']):.3f} | {float(r['max']):.3f} | {float(dynamic[0]['rms']):.3f} |"
        if not line[0].endswith(want):
            failures.append(f"row {r['comparison']}: expected it to end {want}: {line[0]}")
    for c in checks:
        verdict = "PASS" if c["passed"] == "1" else "FAIL"
        if f"| {c['check']} | {float(c['value']):.3f} | {float(c['bound']):g} | {verdict} |" not in table:
            failures.append(f"check {c['check']} missing or wrong")
    if len([r for r in rows if not r["variant"]]) < 2 or not checks:
        failures.append("the quick run wrote fewer rows than expected")
    if failures:
        print(table)
        sys.exit("FAIL: " + "; ".join(failures))
    print(f"ok: {len(rows)} comparisons and {len(checks)} checks tabled")
