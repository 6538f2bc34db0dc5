#!/usr/bin/python3
"""SIGKILL at random moments: every file under a final name is always complete and readable (numpy,
meshio, csv, the checkpoint's checksum); only temporary `<name>.tmp<pid>` files may be partial. A run
killed again and again and restarted from its latest checkpoint each time ends with the same files,
bit for bit, as the run that was never killed; a fresh run or a restart removes the temporary files
the killed processes left."""

import os
import random
import signal
import struct
import subprocess
import time

from io_common import (THREADS, arguments, assert_same_outputs, check, check_outputs_readable, load_csv, main,
                       run, temp_files, write_case)

args = arguments(__doc__)
W = args.workdir
SEED = int(os.environ.get("SLUICE_KILL_SEED", random.randrange(1 << 30)))
rng = random.Random(SEED)
print(f"random seed {SEED} (set SLUICE_KILL_SEED to repeat)", flush=True)

# Frames every 0.02 s and a checkpoint every 0.07 s (between frames: probe samples taken since the
# last frame must be on disk with the checkpoint). The process spends much of its time writing.
CASE = write_case(os.path.join(W, "case.toml"), end=1.5, interval=0.02, checkpoint_interval=0.07)
REFERENCE = os.path.join(W, "reference")
run(args.sluice, CASE, "-o", REFERENCE)


def start(*extra):
    return subprocess.Popen([args.sluice, "run", "-q", "--threads", str(THREADS), *extra],
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)


FRAMES = 76  # frames 0..75 at 0.02 s intervals up to 1.5 s


def frames_out(d):
    """Rows of diagnostics.csv, one per frame written (the file is replaced whole, never partial)."""
    try:
        with open(os.path.join(d, "diagnostics.csv")) as f:
            return f.read().count("\n") - 1
    except FileNotFoundError:
        return 0


def kill_at_random_moment(p, d):
    """SIGKILLs p at a random moment of its run: once a random number of frames are out (so the
    moment does not depend on the machine's speed), plus a random delay. Returns True if it was
    killed, False if the run ended first."""
    target = rng.randint(frames_out(d), FRAMES)
    while p.poll() is None and frames_out(d) < target:
        time.sleep(0.001)
    time.sleep(rng.uniform(0.0, 0.01))
    if p.poll() is not None:
        check(p.returncode == 0, f"run failed with status {p.returncode}: {p.stderr.read().decode()}")
        return False
    p.send_signal(signal.SIGKILL)
    p.wait()
    return True


def checkpoint_time(path):
    with open(path, "rb") as f:
        data = f.read()
    case_length = int.from_bytes(data[16:24], "little")
    return struct.unpack_from("<d", data, 24 + case_length)[0]


def test_killed_runs_leave_only_complete_files_and_restart_exactly():
    kills = temps_seen = 0
    for trial in range(6):
        d = os.path.join(W, f"trial_{trial}")
        p = start(CASE, "-o", d)
        # Up to three kills in a row, each at a random moment, the later ones during restarts.
        for _ in range(rng.randint(1, 3)):
            if not kill_at_random_moment(p, d):
                break
            kills += 1
            temps_seen += len(temp_files(d)) if os.path.isdir(d) else 0
            if os.path.isdir(d):
                check_outputs_readable(d)
            checkpoint = os.path.join(d, "checkpoint.bin")
            if os.path.exists(checkpoint) and checkpoint_time(checkpoint) >= 1.5:
                # Killed after the final checkpoint: every frame is out, only the summary may be missing.
                if not os.path.exists(os.path.join(d, "summary.txt")):
                    open(os.path.join(d, "summary.txt"), "w").write("output (written by the test)\n")
                # No run follows to clear the temporary file of a summary being written when the kill
                # came (a run at the case's end cannot be restarted): that one file may be left.
                for t in temp_files(d):
                    check(t.startswith("summary.txt.tmp"), f"trial {trial}: killed after the last checkpoint, {t} left")
                    os.remove(os.path.join(d, t))
                # Nor the lock of the output directory, which the next run there takes over.
                if os.path.exists(os.path.join(d, ".sluice.lock")):
                    os.remove(os.path.join(d, ".sluice.lock"))
                p = None
                break
            if os.path.exists(checkpoint):
                p = start("--restart", checkpoint)
            else:  # killed before the first checkpoint: start again
                p = start(CASE, "-o", d)
        else:
            check(p.wait(timeout=600) == 0, f"trial {trial}: the last run failed: {p.stderr.read().decode()}")
        check_outputs_readable(d)
        check(temp_files(d) == [], f"trial {trial}: temporary files left after a complete run: {temp_files(d)}")
        assert_same_outputs(REFERENCE, d, f"trial {trial} (killed and restarted) vs uninterrupted")
    print(f"  {kills} kills; {temps_seen} temporary files seen right after them", flush=True)
    check(kills >= 6, "too few kills landed during a run to test anything")


def test_kill_during_writes():
    # Kill as soon as a temporary file is visible: a write is in progress at that moment.
    caught = 0
    for trial in range(4):
        d = os.path.join(W, f"writing_{trial}")
        p = start(CASE, "-o", d)
        while p.poll() is None:
            if os.path.isdir(d) and temp_files(d):
                p.send_signal(signal.SIGKILL)
                p.wait()
                caught += 1
                break
            time.sleep(rng.uniform(0.0, 0.005))
        check_outputs_readable(d)
    print(f"  {caught} of 4 runs killed with a write in progress", flush=True)
    check(caught >= 1, "never caught a write in progress")


def test_kill_right_after_a_checkpoint():
    # Killed just after the first checkpoint (t = 0.07 s, between the frames at 0.06 and 0.08 s): the
    # probe samples up to the checkpoint are already on disk, so the restart continues the series.
    for trial in range(3):
        d = os.path.join(W, f"after_checkpoint_{trial}")
        checkpoint = os.path.join(d, "checkpoint.bin")
        p = start(CASE, "-o", d)
        while not os.path.exists(checkpoint) and p.poll() is None:
            time.sleep(0.0005)
        p.send_signal(signal.SIGKILL)
        p.wait()
        check_outputs_readable(d)
        t = checkpoint_time(checkpoint)
        _, rows = load_csv(os.path.join(d, "probes", "wall_pressure.csv"))
        check(rows[-1, 0] >= t, f"probe rows on disk end at {rows[-1, 0]} s, before the checkpoint at {t} s")
        check(run(args.sluice, "--restart", checkpoint).returncode == 0, "restart")
        assert_same_outputs(REFERENCE, d, f"killed after the checkpoint at {t} s and restarted vs uninterrupted")


# A case with no checkpoints by simulated time: only the ones a run writes by the wall clock
# (output.checkpoint_wall_interval, here 0.3 s) and at its end. The run takes about 2 s (release build).
WALL_CASE = write_case(os.path.join(W, "wall_case.toml"), end=1.5, interval=0.02)
WALL_SET = ("--set", "output.checkpoint_wall_interval=0.3", "--set", "domain.dx=0.12")


def test_a_killed_run_restarts_from_its_wall_clock_checkpoint():
    reference = os.path.join(W, "wall_reference")
    run(args.sluice, WALL_CASE, "-o", reference, *WALL_SET)
    d = os.path.join(W, "wall_killed")
    checkpoint = os.path.join(d, "checkpoint.bin")
    p = start(WALL_CASE, "-o", d, *WALL_SET)
    while not os.path.exists(checkpoint) and p.poll() is None:
        time.sleep(0.01)
    time.sleep(rng.uniform(0.0, 0.5))
    check(p.poll() is None, f"the run ended (status {p.returncode}) before it could be killed")
    p.send_signal(signal.SIGKILL)
    p.wait()
    t = checkpoint_time(checkpoint)
    check(0.0 < t < 1.5, f"the checkpoint by the wall clock is at t = {t} s")
    check(run(args.sluice, "--restart", checkpoint).returncode == 0, "restart")
    assert_same_outputs(reference, d, f"killed after a wall-clock checkpoint at t = {t} s and restarted vs uninterrupted")


def test_sighup_stops_like_ctrl_c():
    # A closed terminal or SSH session: the run stops after its step with its outputs and a checkpoint.
    d = os.path.join(W, "hangup")
    p = start(WALL_CASE, "-o", d, *WALL_SET)
    while frames_out(d) < 3 and p.poll() is None:
        time.sleep(0.01)
    p.send_signal(signal.SIGHUP)
    check(p.wait(timeout=120) == 130, f"status {p.returncode} after SIGHUP, expected 130")
    check(os.path.exists(os.path.join(d, "checkpoint.bin")), "no checkpoint after SIGHUP")
    check_outputs_readable(d)


def test_one_run_per_output_directory():
    d = os.path.join(W, "shared")
    p = start(WALL_CASE, "-o", d, *WALL_SET)
    while frames_out(d) < 1 and p.poll() is None:
        time.sleep(0.01)
    check(p.poll() is None, "the first run ended too soon")
    for second in (["run", "-q", WALL_CASE, "-o", d], ["validate", "-q", "--quick", "-o", d]):
        r = subprocess.run([args.sluice, *second], capture_output=True, text=True, timeout=120)
        check(r.returncode == 1, f"{second[0]} into a directory in use: status {r.returncode}\n{r.stderr}")
        check(f"sluice: error: {d}: the output directory is in use by 'sluice run " in r.stderr and
              f"(process {p.pid} on " in r.stderr and "write to another directory (-o)" in r.stderr,
              f"{second[0]}: unexpected message:\n{r.stderr}")
    # A killed holder's lock is taken over; the next run ends with the directory as a run leaves it.
    p.send_signal(signal.SIGKILL)
    p.wait()
    check(os.path.exists(os.path.join(d, ".sluice.lock")), "the killed run left no lock file to take over")
    run(args.sluice, WALL_CASE, "-o", d, "--set", "time.end=0.05")
    check(not os.path.exists(os.path.join(d, ".sluice.lock")), "the lock file outlived the run that held it")


main([test_killed_runs_leave_only_complete_files_and_restart_exactly, test_kill_during_writes,
      test_kill_right_after_a_checkpoint, test_a_killed_run_restarts_from_its_wall_clock_checkpoint,
      test_sighup_stops_like_ctrl_c, test_one_run_per_output_directory])
