#!/usr/bin/python3
"""diagnostics.csv, the .pvd collection and the probe series grow in place: while a run writes its
frames, and across a restart that keeps all their rows, each file keeps its inode and its earlier bytes
(the .pvd's before its closing tags), so a frame's output costs the same at the end of a run as at its
start. A file rewritten whole at every frame (a new file renamed over the old one) fails this."""

import os
import subprocess
import time

from io_common import (THREADS, arguments, assert_same_outputs, check, check_outputs_readable, load_pvd, main, run,
                       write_case)

args = arguments(__doc__)
W = args.workdir
PVD_FOOTER = b"  </Collection>\n</VTKFile>\n"
GROWING = {  # file -> what it ends with after every write
    "diagnostics.csv": b"\n",
    "io_test.pvd": PVD_FOOTER,
    os.path.join("probes", "wall_pressure.csv"): b"\n",
    os.path.join("probes", "gauge_mid.csv"): b"\n",
    os.path.join("probes", "surface_mid.csv"): b"\n",
    os.path.join("probes", "front.csv"): b"\n",
}


def body(name, data):
    """The bytes a later write must leave unchanged: all of a CSV, the .pvd without its footer."""
    return data[:-len(PVD_FOOTER)] if name.endswith(".pvd") else data


def read_state(directory, name):
    """(inode, bytes) of a file, or None if it is missing or was written to while being read."""
    path = os.path.join(directory, name)
    try:
        fd = os.open(path, os.O_RDONLY)
    except FileNotFoundError:
        return None
    try:
        before = os.fstat(fd)
        data = os.pread(fd, before.st_size, 0)
        after = os.fstat(fd)
    finally:
        os.close(fd)
    unchanged = len(data) == before.st_size == after.st_size and after.st_mtime_ns == before.st_mtime_ns
    return (before.st_ino, data) if unchanged and data.endswith(GROWING[name]) else None


def check_grows_in_place(name, states, what):
    """Every state keeps the inode and the body of the one before it."""
    for (inode_a, a), (inode_b, b) in zip(states, states[1:]):
        check(inode_b == inode_a, f"{what}: {name} was replaced by a new file (inode {inode_a} -> {inode_b}) "
                                  f"when it grew from {len(a)} to {len(b)} bytes")
        check(b.startswith(body(name, a)), f"{what}: {name}: its first {len(body(name, a))} bytes were rewritten")


def test_files_grow_in_place_while_a_run_writes_frames():
    # 201 frames, one every 0.01 s: the files are watched between frames as the run goes.
    case = write_case(os.path.join(W, "watched.toml"), end=2.0, interval=0.01)
    d = os.path.join(W, "watched")
    p = subprocess.Popen([args.sluice, "run", "-q", "--threads", str(THREADS), case, "-o", d],
                         stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    states = {name: [] for name in GROWING}
    while p.poll() is None:
        for name, seen in states.items():
            state = read_state(d, name)
            if state is not None and (not seen or state[1] != seen[-1][1]):
                seen.append(state)
        time.sleep(0.002)
    check(p.returncode == 0, f"run failed: {p.stderr.read().decode()}")
    for name, seen in states.items():
        final = read_state(d, name)
        check(final is not None, f"{name}: missing or incomplete after the run")
        seen.append(final)
        check(len(seen) >= 4, f"{name}: seen in only {len(seen)} states during the run")
        check_grows_in_place(name, seen, "during the run")
    check(len(load_pvd(os.path.join(d, "io_test.pvd"))) == 201, "the .pvd lists every frame")
    check_outputs_readable(d)
    print("  states seen: " + ", ".join(f"{name} {len(seen)}" for name, seen in states.items()), flush=True)


def test_a_restart_continues_the_same_files():
    case = write_case(os.path.join(W, "restart.toml"), end=1.0, interval=0.1, checkpoint_interval=0.5)
    reference = os.path.join(W, "reference")
    run(args.sluice, case, "-o", reference)
    d = os.path.join(W, "restarted")
    run(args.sluice, case, "-o", d, "--set", "time.end=0.5")
    before = {name: read_state(d, name) for name in GROWING}
    run(args.sluice, "--restart", os.path.join(d, "checkpoint.bin"), "--set", "time.end=1.0")
    for name, state in before.items():
        check(state is not None, f"{name}: missing after the first half")
        check_grows_in_place(name, [state, read_state(d, name)], "across the restart")
    assert_same_outputs(reference, d, "restarted at 0.5 s vs uninterrupted")


main([test_files_grow_in_place_while_a_run_writes_frames, test_a_restart_continues_the_same_files])
