#!/usr/bin/python3
"""Resource failures outside `sluice run`'s own outputs (those are test_output_errors.py): `sluice init`
into an unwritable place or past a file-size limit, a restart into an unwritable directory, and a
missing input for every command that reads one. Each must give `sluice: error: <path>: <reason>`, a
non-zero exit status, nothing on stdout, and no file (complete, partial or temporary) under the name
that was to be written."""

import os
import re
import resource
import subprocess

from io_common import arguments, check, main, run, temp_files, write_case

args = arguments(__doc__)
W = args.workdir


def sluice(*argv, limit=None, cwd=None):
    preexec = None
    if limit is not None:
        def preexec():
            resource.setrlimit(resource.RLIMIT_FSIZE, (limit, resource.RLIM_INFINITY))
    return subprocess.run([os.path.abspath(args.sluice), *argv], capture_output=True, text=True, timeout=600, preexec_fn=preexec,
                          cwd=cwd)


def expect_error(r, status, *parts):
    check(r.returncode == status, f"exit status {r.returncode}, expected {status}\n{r.stderr}")
    check(r.stdout == "", f"a failed command printed on stdout:\n{r.stdout}")
    check(r.stderr.startswith("sluice: error: "), f"expected 'sluice: error: ...', got:\n{r.stderr}")
    for part in parts:
        check(part in r.stderr, f"expected '{part}' in:\n{r.stderr}")


def test_init_into_an_unwritable_place():
    # /proc/self exists but nothing can be created in it, even by root.
    r = sluice("init", "/proc/self/case.toml")
    expect_error(r, 1, "/proc/self/case.toml: cannot create (")
    check(not os.path.exists("/proc/self/case.toml"), "a file appeared")


def test_init_past_a_file_size_limit_leaves_no_file():
    # The template is about 10 kB; a 4 kB limit (ulimit -f) stops the write part way.
    d = os.path.join(W, "init_limited")
    os.makedirs(d)
    r = sluice("init", "case.toml", limit=4096, cwd=d)
    expect_error(r, 1, "case.toml: cannot write (File too large)")
    check(os.listdir(d) == [], f"files left: {os.listdir(d)}")
    # Without the limit it is written, and `sluice run` accepts it: the failure above was the limit.
    r = sluice("init", "case.toml", cwd=d)
    check(r.returncode == 0 and os.path.getsize(os.path.join(d, "case.toml")) > 4096, r.stderr)


def test_restart_into_an_unwritable_directory_changes_nothing():
    d = os.path.join(W, "restart")
    case = write_case(os.path.join(W, "case.toml"), end=0.2, interval=0.1)
    run(args.sluice, case, "-o", d)
    before = {n: os.path.getsize(os.path.join(d, n)) for n in os.listdir(d)}
    r = run(args.sluice, "--restart", os.path.join(d, "checkpoint.bin"), "--set", "time.end=0.4", "-o", "/proc/self",
            expect=1)
    check(r.stderr.startswith("sluice: error: /proc/self/"), f"expected an error naming /proc/self/...:\n{r.stderr}")
    check(r.stdout == "", f"a failed restart printed a summary:\n{r.stdout}")
    after = {n: os.path.getsize(os.path.join(d, n)) for n in os.listdir(d)}
    check(after == before, f"the checkpoint's directory changed: {before} -> {after}")
    check(temp_files(d) == [], f"temporary files left: {temp_files(d)}")


def test_a_missing_input_is_a_clear_error_for_every_command_that_reads_one():
    d = os.path.join(W, "missing")
    os.makedirs(d)
    nope = os.path.join(d, "nope")
    attempts = [
        (("run", nope + ".toml"), 2, "no such case file"),
        (("run", "-q", "--restart", nope + ".bin"), 1, "no such checkpoint file"),
    ]
    # Commands that read a run's output directory, where this build has them.
    listed = sluice("--help").stdout
    for command in ("render", "analyze"):
        if re.search(rf"^\s+{command}\s", listed, re.MULTILINE):
            attempts.append(((command, nope), 2, "no such directory"))
    for argv, status, reason in attempts:
        r = sluice(*argv, cwd=d)
        expect_error(r, status, nope, reason)
        check(os.listdir(d) == [], f"sluice {' '.join(argv)} left files: {os.listdir(d)}")
    print(f"  missing inputs checked for: {', '.join(' '.join(a[:1] + (('--restart',) if '--restart' in a else ())) for a, _, _ in attempts)}")


main([test_init_into_an_unwritable_place, test_init_past_a_file_size_limit_leaves_no_file,
      test_restart_into_an_unwritable_directory_changes_nothing,
      test_a_missing_input_is_a_clear_error_for_every_command_that_reads_one])
