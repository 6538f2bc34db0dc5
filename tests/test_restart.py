#!/usr/bin/python3
"""`sluice run --restart CHECKPOINT` continues a run bit for bit: the frames, the collection, the
diagnostics and the probe series of a run that was stopped (at its end, or by Ctrl-C) and restarted
are byte-identical to those of the run that never stopped (same thread count). A damaged, truncated or
other-version checkpoint, or a restart that cannot continue, is a clear error that changes nothing."""

import os
import signal
import subprocess
import time

from io_common import (THREADS, arguments, assert_same_outputs, check, check_outputs_readable, final_files, load_pvd,
                       main, run, write_case)

args = arguments(__doc__)
W = args.workdir
CASE = write_case(os.path.join(W, "case.toml"), end=1.0, interval=0.1, checkpoint_interval=0.5)

# The run that never stopped.
REFERENCE = os.path.join(W, "reference")
run(args.sluice, CASE, "-o", REFERENCE)


def snapshot(directory):
    out = {}
    for name in final_files(directory):
        with open(os.path.join(directory, name), "rb") as f:
            out[name] = f.read()
    return out


def test_run_to_half_then_restart_with_a_later_end():
    for threads in (THREADS, 2):  # the same thread count in both runs; two exercise the parallel paths
        reference = REFERENCE if threads == THREADS else os.path.join(W, f"reference_{threads}_threads")
        if not os.path.exists(reference):
            run(args.sluice, CASE, "-o", reference, threads=threads)
        d = os.path.join(W, f"halves_{threads}_threads")
        run(args.sluice, CASE, "-o", d, "--set", "time.end=0.5", threads=threads)
        check(len(load_pvd(os.path.join(d, "io_test.pvd"))) == 6, "first half: frames 0..5")
        r = run(args.sluice, "--restart", os.path.join(d, "checkpoint.bin"), "--set", "time.end=1.0",
                threads=threads)
        check("finished at t = 1.0000 s" in r.stdout, r.stdout)
        check_outputs_readable(d)
        n = assert_same_outputs(reference, d, f"restarted at 0.5 s vs uninterrupted, {threads} threads")
        check(n >= 25, f"only {n} files compared")


def test_leapfrog_run_to_half_then_restart():
    # The leapfrog carries the rates of a step's end into the next step: the checkpoint holds them, so
    # the restart continues without evaluating anew, bit for bit (on two threads: the parallel paths).
    reference = os.path.join(W, "leapfrog_reference")
    run(args.sluice, CASE, "-o", reference, "--set", "time.integrator=leapfrog", threads=2)
    d = os.path.join(W, "leapfrog_halves")
    run(args.sluice, CASE, "-o", d, "--set", "time.integrator=leapfrog", "--set", "time.end=0.5", threads=2)
    r = run(args.sluice, "--restart", os.path.join(d, "checkpoint.bin"), "--set", "time.end=1.0", threads=2)
    check("(1 force evaluation per step)" in r.stdout, r.stdout)
    n = assert_same_outputs(reference, d, "leapfrog restarted at 0.5 s vs uninterrupted")
    check(n >= 25, f"only {n} files compared")


def test_an_end_time_that_is_a_frame_time_up_to_rounding():
    # Frame 3 is at 3 * 0.1 = 0.30000000000000004 s; a run with time.end = 0.3 stops there too, so
    # its checkpoint continues the longer run exactly.
    d = os.path.join(W, "rounding")
    run(args.sluice, CASE, "-o", d, "--set", "time.end=0.3")
    times = [t for t, _ in load_pvd(os.path.join(d, "io_test.pvd"))]
    check(times == [0.0, 0.1, 0.2, 3 * 0.1], f"frame times {times}")
    run(args.sluice, "--restart", os.path.join(d, "checkpoint.bin"), "--set", "time.end=1.0")
    assert_same_outputs(REFERENCE, d, "restarted at 0.3 s vs uninterrupted")


def test_ctrl_c_then_restart():
    # Ctrl-C (SIGINT) mid-run: the run stops after the current step, writes the last frame (at that
    # time, between two regular frame times), a checkpoint and the summary, and exits with status 130.
    # Its restart drops that extra frame and ends with exactly the files of the uninterrupted run.
    long_case = write_case(os.path.join(W, "long.toml"), end=4.0, interval=1.0, checkpoint_interval=0.0)
    reference = os.path.join(W, "long_reference")
    run(args.sluice, long_case, "-o", reference)
    between_frames = 0
    for attempt in range(10):
        d = os.path.join(W, f"interrupted_{attempt}")
        p = subprocess.Popen([args.sluice, "run", "-q", "--threads", str(THREADS), long_case, "-o", d],
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        # Once frame 1 (t = 1 s) is out, interrupt a little later (most of the time between frames is
        # spent stepping, but writing a frame, with its fsyncs, can take as long).
        while not os.path.exists(os.path.join(d, "frames", "frame_000001.npz")) and p.poll() is None:
            time.sleep(0.001)
        time.sleep(0.015 * attempt)
        p.send_signal(signal.SIGINT)
        out, err = p.communicate(timeout=300)
        check(p.returncode == 130, f"exit status {p.returncode} after SIGINT, expected 130\n{err}")
        check("stopped on request" in out, out)
        check_outputs_readable(d)
        last_time = load_pvd(os.path.join(d, "io_test.pvd"))[-1][0]
        between_frames += last_time % 1.0 != 0.0
        run(args.sluice, "--restart", os.path.join(d, "checkpoint.bin"))
        assert_same_outputs(reference, d, f"Ctrl-C at t = {last_time} s and restart vs uninterrupted")
        if between_frames >= 2:
            break
    print(f"  {between_frames} of {attempt + 1} interruptions fell between two frame times")
    check(between_frames >= 1, "no interruption fell between two frame times")


def test_bad_checkpoints_are_clear_errors_and_change_nothing():
    d = os.path.join(W, "bad")
    run(args.sluice, CASE, "-o", d, "--set", "time.end=0.5")
    good_path = os.path.join(d, "checkpoint.bin")
    with open(good_path, "rb") as f:
        good = f.read()
    before = snapshot(d)

    def attempt(content, expected_message, name="checkpoint.bin", status=1, extra=()):
        path = os.path.join(d, name)
        if content is not None:
            with open(path, "wb") as f:
                f.write(content)
        r = run(args.sluice, "--restart", path, *extra, expect=status)
        names = expected_message.split(":")[0] if expected_message.startswith("--set") else path
        check(f"sluice: error: {names}" in r.stderr, f"message does not start with '{names}':\n{r.stderr}")
        check(expected_message in r.stderr, f"expected '{expected_message}' in:\n{r.stderr}")
        if name == "checkpoint.bin":
            with open(path, "wb") as f:
                f.write(good)
        after = snapshot(d)
        after.pop(name, None)
        expected = dict(before)
        expected.pop(name, None)
        check(after == expected, f"a failed restart changed the outputs: {sorted(set(after) ^ set(expected))}")

    flipped = bytearray(good)
    flipped[len(good) // 2] ^= 0x10
    attempt(bytes(flipped), "not a usable checkpoint: checksum mismatch (the file is damaged or incomplete)")
    attempt(good[: len(good) - 1000], "checksum mismatch (the file is damaged or incomplete)")
    other_version = bytearray(good)
    other_version[8:12] = (99).to_bytes(4, "little")
    attempt(bytes(other_version), "not a usable checkpoint: format version 99, this sluice reads versions 2 to 7")
    attempt(b"time,step\n0,0\n" * 10, "it does not start with the sluice checkpoint signature")
    attempt(None, f"no such checkpoint file; {d} holds frames of a run that stopped before writing one", name="missing.bin")
    attempt(None, "a run writes its checkpoint every output.checkpoint_wall_interval seconds", name="missing.bin")
    # The checkpoint is at the end of its run (0.5 s): continuing needs a later end.
    attempt(good, "already at the case's end (time.end = 0.5 s)", status=2)
    attempt(good, "--set domain.dx=0.2: a restart continues the case stored in", status=2,
            extra=("--set", "time.end=1.0", "--set", "domain.dx=0.2"))
    attempt(good, "--set time.end=abc: time.end = ", status=2, extra=("--set", "time.end=abc"))


main([test_run_to_half_then_restart_with_a_later_end, test_leapfrog_run_to_half_then_restart,
      test_an_end_time_that_is_a_frame_time_up_to_rounding,
      test_ctrl_c_then_restart, test_bad_checkpoints_are_clear_errors_and_change_nothing])
