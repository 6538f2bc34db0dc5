#!/usr/bin/python3
"""`mpirun -np N sluice run` (Open MPI, N = 2, 3, 4 on one machine): the same outputs, in the same form,
as one process, with the particles where one process puts them to round-off (also with a moving wall); a checkpoint written by 3
processes restarts on 2 and on 1; a failure stops every process with one message and no hang."""

import glob
import os
import signal
import subprocess
import time

import numpy as np

from io_common import (arguments, check, check_outputs_readable, final_files, load_csv, load_npz, load_pvd, main,
                       run, write_case)

args = arguments(__doc__)
W = args.workdir
CASE = write_case(os.path.join(W, "case.toml"), end=1.0, interval=0.1, checkpoint_interval=0.5)
ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1", OMP_WAIT_POLICY="PASSIVE")
# Round-off: the processes add the same pair terms in another order. Over the 1 s of the case (about 600
# steps of a splashing dam break) the difference grows from 1e-16 m but stays many orders below the
# particle spacing (0.4 m); a lost pair, a stale ghost or a lost particle moves particles by 1e-3 m and
# more within a few steps.
POSITION_TOLERANCE = 1e-6

REFERENCE = os.path.join(W, "serial")
run(args.sluice, CASE, "-o", REFERENCE)


def mpirun(processes, *sluice_args, expect=0, timeout=300):
    command = ["mpirun", "--oversubscribe", "-np", str(processes), args.sluice, "run", "-q", "--threads", "1",
               *sluice_args]
    r = subprocess.run(command, capture_output=True, text=True, timeout=timeout, env=ENV)
    if expect is not None and r.returncode != expect:
        raise AssertionError(f"{' '.join(command)}: exit status {r.returncode}, expected {expect}\n"
                             f"stdout:\n{r.stdout}\nstderr:\n{r.stderr}")
    return r


def largest_difference(a, b, what):
    """Frames and probe series of two runs: the same files, rows and particles (in id order); returns
    the largest position difference over all frames."""
    names_a, names_b = final_files(a), final_files(b)
    check(names_a == names_b, f"{what}: different files:\n  {names_a}\n  {names_b}")
    worst = 0.0
    for name in names_a:
        if name.endswith(".npz"):
            fa, fb = load_npz(os.path.join(a, name)), load_npz(os.path.join(b, name))
            check(np.array_equal(fa["id"], fb["id"]) and np.array_equal(fa["id"], np.arange(len(fa["id"]))),
                  f"{what}: {name}: particles not in id order 0..N-1")
            check(np.array_equal(fa["kind"], fb["kind"]), f"{what}: {name}: kinds differ")
            check(fa["t"] == fb["t"], f"{what}: {name}: time {fa['t']} vs {fb['t']}")
            worst = max(worst, float(np.max(np.abs(fa["x"] - fb["x"]))))
        elif name.endswith(".csv"):
            ha, va = load_csv(os.path.join(a, name))
            hb, vb = load_csv(os.path.join(b, name))
            check(ha == hb and va.shape == vb.shape, f"{what}: {name}: {va.shape} rows vs {vb.shape}")
            check(np.allclose(va[:, 0], vb[:, 0], rtol=1e-9, atol=1e-12), f"{what}: {name}: sample times differ")
            if name.startswith("probes"):
                # Pressures (Pa), heights and front positions (m), summed over the processes.
                worst_probe = float(np.max(np.abs(va - vb))) if va.size else 0.0
                check(np.allclose(va, vb, rtol=1e-9, atol=1e-6), f"{what}: {name}: values differ by {worst_probe}")
        elif name.endswith(".pvd"):
            check(load_pvd(os.path.join(a, name)) == load_pvd(os.path.join(b, name)), f"{what}: {name} differs")
    return worst


def test_frames_probes_and_diagnostics_match_one_process():
    for processes in (2, 3, 4):
        d = os.path.join(W, f"np{processes}")
        r = mpirun(processes, CASE, "-o", d)
        check(r.stdout.count("finished at t = 1.0000 s") == 1, f"one summary expected:\n{r.stdout}")
        check(f"processes   {processes}" in r.stdout, r.stdout)
        check_outputs_readable(d)
        worst = largest_difference(REFERENCE, d, f"{processes} processes vs 1")
        print(f"  {processes} processes: largest position difference from one process over 11 frames "
              f"{worst:.3g} m", flush=True)
        check(worst < POSITION_TOLERANCE, f"{processes} processes: positions differ by {worst} m")


def test_two_processes_of_two_threads_match_one_process():
    # MPI and OpenMP together: --threads is per process (4 threads on 2 processes here).
    d = os.path.join(W, "np2_threads2")
    command = ["mpirun", "--oversubscribe", "-np", "2", args.sluice, "run", "-q", "--threads", "2", CASE, "-o", d]
    r = subprocess.run(command, capture_output=True, text=True, timeout=300, env=ENV)
    check(r.returncode == 0, f"exit status {r.returncode}\n{r.stderr}")
    worst = largest_difference(REFERENCE, d, "2 processes x 2 threads vs 1 process")
    print(f"  2 processes x 2 threads: largest position difference from one process {worst:.3g} m", flush=True)
    check(worst < POSITION_TOLERANCE, f"2 processes x 2 threads: positions differ by {worst} m")


def test_checkpoint_of_three_processes_restarts_on_two_and_on_one():
    d = os.path.join(W, "three_then")
    mpirun(3, CASE, "-o", d, "--set", "time.end=0.5")
    checkpoint = os.path.join(d, "checkpoint.bin")
    for processes in (2, 1):
        out = os.path.join(W, f"restart_on_{processes}")
        if processes == 1:
            run(args.sluice, "--restart", checkpoint, "-o", out, "--set", "time.end=1.0")
        else:
            mpirun(processes, "--restart", checkpoint, "-o", out, "--set", "time.end=1.0")
        last = load_npz(os.path.join(out, "frames", "frame_000010.npz"))
        ref = load_npz(os.path.join(REFERENCE, "frames", "frame_000010.npz"))
        check(np.array_equal(last["id"], ref["id"]), f"restart on {processes}: particles differ")
        worst = float(np.max(np.abs(last["x"] - ref["x"])))
        print(f"  3 processes to 0.5 s, then {processes} to 1 s: largest position difference at 1 s {worst:.3g} m",
              flush=True)
        check(worst < POSITION_TOLERANCE, f"restart on {processes}: positions differ by {worst} m")


def matches_one_process(label, key, case_args, extra=None):
    """Runs the case on one process, then on 2 and 3: every particle within POSITION_TOLERANCE of where
    one process put it. extra(reference, directory, processes) adds checks of its own and returns the
    words to print after the particles' difference."""
    reference = os.path.join(W, f"{key}_serial")
    run(args.sluice, *case_args, "-o", reference)
    for processes in (2, 3):
        d = os.path.join(W, f"{key}_np{processes}")
        mpirun(processes, *case_args, "-o", d)
        worst = largest_difference(reference, d, f"{label}, {processes} processes vs 1")
        more = extra(reference, d, processes) if extra else ""
        print(f"  {label}, {processes} processes: largest position difference from one process {worst:.3g} m{more}",
              flush=True)
        check(worst < POSITION_TOLERANCE, f"{label}, {processes} processes: positions differ by {worst} m")


def test_a_moving_gate_across_the_processes_matches_one_process():
    # gate_dam_break, coarsened: its gate rises through every process's region, and its particles and
    # ghost nodes cross from one process to another.
    matches_one_process("moving gate", "gate", ["gate_dam_break", "--set", "domain.dx=0.01", "--set", "time.end=0.15",
                                                "--set", "output.interval=0.05"])


ROLLED_TANK = """
[case]
name = "rolled_tank"
[domain]
dx = 0.01
[tank]
width = 0.6
height = 0.3
lid = true
[tank.rotation]
law = "sinusoidal"
centre = [0.3, 0.15]
amplitude = 6.0
period = 1.0
[fluid]
sound_speed = 15.0
[time]
end = 0.3
[output]
interval = 0.1
[[water]]
min = [0.0, 0.0]
max = [0.6, 0.1]
"""


def test_a_moving_tank_across_the_processes_matches_one_process():
    # The tank's own walls rolled by 6 degrees: every process's wall particles and ghost nodes move, and
    # cross from one process to another.
    case = os.path.join(W, "rolled_tank.toml")
    with open(case, "w") as f:
        f.write(ROLLED_TANK)
    matches_one_process("moving tank", "tank", [case])


def test_a_floating_body_across_the_processes_matches_one_process():
    # floating_box, coarsened: the box falls into the water across the processes' boundary (its load is
    # summed over the processes, each counting only the particles it owns, not its ghosts).
    def centre_of_gravity(reference, d, processes):
        ha, va = load_csv(os.path.join(reference, "bodies", "box.csv"))
        hb, vb = load_csv(os.path.join(d, "bodies", "box.csv"))
        check(ha == hb and va.shape == vb.shape, f"floating box, {processes} processes: bodies/box.csv rows differ")
        drift = float(np.max(np.abs(va[:, 1:3] - vb[:, 1:3])))
        check(drift < POSITION_TOLERANCE, f"floating box, {processes} processes: the body's position differs by {drift} m")
        return f", of its centre of gravity {drift:.3g} m"

    matches_one_process("floating box", "box", ["floating_box", "--set", "domain.dx=0.02", "--set", "time.end=0.2",
                                                "--set", "output.interval=0.1"], centre_of_gravity)


def test_an_output_error_stops_every_process_with_one_message():
    blocker = os.path.join(W, "a_file")
    with open(blocker, "w") as f:
        f.write("not a directory\n")
    r = mpirun(3, CASE, "-o", os.path.join(blocker, "out"), expect=1, timeout=120)
    check(r.stderr.count("sluice: error:") == 1, f"one error message expected:\n{r.stderr}")
    check("a_file" in r.stderr, r.stderr)


def test_an_unstable_run_stops_every_process_and_keeps_the_last_good_state():
    d = os.path.join(W, "unstable")
    r = mpirun(2, CASE, "-o", d, "--set", "time.dt=0.2", "--set", "output.interval=0.2", expect=1, timeout=120)
    check(r.stderr.count("became unstable") == 1, f"one instability message expected:\n{r.stderr}")
    check(os.path.exists(os.path.join(d, "checkpoint.bin")), "no checkpoint of the last good state")
    check_outputs_readable(d)


def sanitized():
    """AddressSanitizer reserves terabytes of address space: an address-space limit stops it at start."""
    r = subprocess.run(["ldd", args.sluice], capture_output=True, text=True)
    return "libasan" in r.stdout


def test_a_process_out_of_memory_stops_every_process_with_its_message():
    if sanitized():
        print("  (skipped under AddressSanitizer)", flush=True)
        return
    # Process 1 of 2 gets too little address space for the set-up (every process builds the whole case
    # at dx = 0.01 m, 508k particles, before keeping its share) while process 0 waits for it.
    r = subprocess.run(["mpirun", "--oversubscribe", "-np", "1", args.sluice, "run", "-q", "--threads", "1",
                        "--set", "domain.dx=0.01", "--set", "time.end=0.01", "-o", os.path.join(W, "oom"), ":",
                        "-np", "1", "sh", "-c",
                        f"ulimit -v 250000; exec {args.sluice} run -q --threads 1 --set domain.dx=0.01 "
                        f"--set time.end=0.01 -o {os.path.join(W, 'oom')}"],
                       capture_output=True, text=True, timeout=120, env=ENV)
    check(r.returncode != 0, f"exit status {r.returncode}\n{r.stderr}")
    check(r.stderr.count("sluice: error:") == 1, f"one error message expected:\n{r.stderr}")
    check("process 1 of 2: out of memory" in r.stderr, r.stderr)


def test_a_killed_process_ends_the_run_with_an_error():
    d = os.path.join(W, "killed")
    command = ["mpirun", "--oversubscribe", "-np", "2", args.sluice, "run", "-q", "--threads", "1", CASE, "-o", d,
               "--set", "time.end=1000", "--set", "output.interval=1.0"]
    p = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=ENV)
    deadline = time.time() + 60
    victims = []
    while time.time() < deadline and not victims:
        time.sleep(0.5)
        victims = [int(path.split("/")[2]) for path in glob.glob("/proc/[0-9]*/stat")
                   if _parent(path) == p.pid and _name(path) == "sluice"]
    check(victims, "no sluice process started under mpirun")
    time.sleep(1.0)  # into the stepping loop
    os.kill(victims[-1], signal.SIGKILL)
    try:
        _, err = p.communicate(timeout=60)
    except subprocess.TimeoutExpired:
        p.kill()
        raise AssertionError("the run hung after one of its processes was killed")
    check(p.returncode != 0, "a run with a killed process must end with a non-zero status")


def _parent(stat_path):
    try:
        with open(stat_path) as f:
            return int(f.read().rsplit(")", 1)[1].split()[1])
    except (OSError, IndexError, ValueError):
        return -1


def _name(stat_path):
    try:
        with open(stat_path) as f:
            text = f.read()
        return text[text.index("(") + 1:text.rindex(")")]
    except (OSError, ValueError):
        return ""


main([test_frames_probes_and_diagnostics_match_one_process, test_two_processes_of_two_threads_match_one_process,
      test_checkpoint_of_three_processes_restarts_on_two_and_on_one,
      test_a_moving_gate_across_the_processes_matches_one_process,
      test_a_moving_tank_across_the_processes_matches_one_process,
      test_a_floating_body_across_the_processes_matches_one_process,
      test_an_output_error_stops_every_process_with_one_message,
      test_an_unstable_run_stops_every_process_and_keeps_the_last_good_state,
      test_a_process_out_of_memory_stops_every_process_with_its_message,
      test_a_killed_process_ends_the_run_with_an_error])
