#!/usr/bin/python3
"""Output failures are clear errors: an output directory that cannot be created or written, a file-size
limit (ulimit -f) and a full disk each give `sluice: error: <file>: <reason>` and exit status 1, never a
crash, and leave no partial file under a final name (the files written before the failure stay
complete and readable)."""

import os
import re
import resource
import subprocess
import sys
import time

from io_common import (arguments, check, check_outputs_readable, final_files, main, run, temp_files,
                       write_case)

INNER = "--inner" in sys.argv
if INNER:
    sys.argv.remove("--inner")
args = arguments(__doc__)
W = args.workdir
CASE = write_case(os.path.join(W, "case.toml"), end=1.0, interval=0.1)


def expect_error(output_dir, message, *extra, limit=None):
    """Runs into output_dir expecting exit status 1 and `sluice: error: <message>` on stderr (a regular
    expression)."""
    preexec = None
    if limit is not None:
        def preexec():
            resource.setrlimit(resource.RLIMIT_FSIZE, (limit, resource.RLIM_INFINITY))
    r = run(args.sluice, CASE, "-o", output_dir, *extra, expect=1, preexec_fn=preexec)
    check(r.stderr.startswith("sluice: error: ") and re.search(message, r.stderr),
          f"expected 'sluice: error: ...{message}...', got:\n{r.stderr}")
    check(r.stdout == "", f"a failed run printed a summary:\n{r.stdout}")
    return r


def test_output_directory_that_cannot_be_created():
    a_file = os.path.join(W, "a_file")
    with open(a_file, "w") as f:
        f.write("not a directory\n")
    expect_error("/proc/sluice_no_such_dir/out", r"/proc/sluice_no_such_dir/out: cannot create directory \(")
    expect_error(os.path.join(a_file, "out"), rf"{a_file}/out: cannot create directory \(Not a directory\)")
    expect_error(a_file, f"{a_file}: exists and is not a directory")
    # A directory in which nothing can be created (even by root): /proc/self exists, its sub-directories
    # (frames/, probes/) cannot.
    expect_error("/proc/self", r"/proc/self/(frames|probes|\.sluice\.lock): cannot create( directory)? \(")


def test_file_size_limit_is_a_clear_error():
    # ulimit -f: the first frame's .npz (about 44 kB) fits under 60 kB, its .vtu (about 70 kB) does not.
    d = os.path.join(W, "limited")
    expect_error(d, rf"{d}/frames/frame_000000\.vtu: cannot write \(File too large\)", limit=60_000)
    names = check_outputs_readable(d)
    check(names == ["frames/frame_000000.npz"], f"files after the failure: {names}")
    check(temp_files(d) == [], f"temporary files left: {temp_files(d)}")


def test_full_disk_in_a_private_tmpfs():
    # A real full disk (ENOSPC): a small tmpfs mounted in a private mount namespace (root only).
    inner = subprocess.run(["unshare", "--mount", "--propagation", "private", sys.executable, __file__, "--inner",
                            "--sluice", args.sluice, "--workdir", os.path.join(W, "namespace")],
                           capture_output=True, text=True, timeout=600)
    sys.stdout.write("".join("    " + line + "\n" for line in inner.stdout.splitlines()))
    if inner.returncode == 77:
        print("  (skipped: no permission to create a mount namespace and a tmpfs; the file-size limit test "
              "covers the same code path)")
        return
    check(inner.returncode == 0, f"in the private tmpfs: status {inner.returncode}\n{inner.stdout}\n{inner.stderr}")


def inner_full_disk():
    # A run that plans more frames than the disk holds is refused before it writes anything.
    small = os.path.join(W, "small")
    os.makedirs(small)
    if subprocess.run(["mount", "-t", "tmpfs", "-o", "size=600k", "tmpfs", small], capture_output=True).returncode:
        sys.exit(77)
    d = os.path.join(small, "out")
    r = expect_error(d, rf"{d}: the run would write about [0-9.e-]+ GB of frames \(11 frames of [0-9]+ particles\), "
                        rf"and {small} has [0-9.e-]+ GB free")
    check(not os.path.exists(d), f"a refused run left {final_files(d)}")
    print(f"refused up front: {r.stderr.strip()}")

    # The disk fills while the run goes (another process writes to it): the run stops with a clear
    # error, and what it wrote before stays complete and readable.
    room = os.path.join(W, "room")
    os.makedirs(room)
    if subprocess.run(["mount", "-t", "tmpfs", "-o", "size=40m", "tmpfs", room], capture_output=True).returncode:
        sys.exit(77)
    d = os.path.join(room, "out")
    long_case = write_case(os.path.join(W, "long_case.toml"), end=30.0, interval=0.1)
    p = subprocess.Popen([args.sluice, "run", "-q", "--threads", "1", long_case, "-o", d], stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE, text=True)
    while p.poll() is None and not os.path.exists(os.path.join(d, "frames", "frame_000002.vtu")):
        time.sleep(0.005)
    try:
        with open(os.path.join(room, "filler"), "wb") as f:
            while True:
                f.write(b"\0" * 65536)
                f.flush()
    except OSError:
        pass
    out, err = p.communicate(timeout=600)
    check(p.returncode == 1, f"status {p.returncode} on a full disk\n{err}")
    check(err.startswith(f"sluice: error: {d}/") and "No space left on device" in err,
          f"the message does not name the file and the reason:\n{err}")
    check(out == "", f"a failed run printed a summary:\n{out}")
    names = check_outputs_readable(d)
    frames = [n for n in names if n.endswith(".npz")]
    check(len(frames) >= 2, f"expected the failure mid-run, after some frames: {names}")
    check(temp_files(d) == [], f"temporary files left: {temp_files(d)}")
    print(f"disk full after {len(frames)} frames: {err.strip()}")


def inner_read_only():
    ro = os.path.join(W, "read_only")
    os.makedirs(ro)
    if subprocess.run(["mount", "-t", "tmpfs", "-o", "ro,size=10m", "tmpfs", ro], capture_output=True).returncode:
        sys.exit(77)
    expect_error(ro, rf"{ro}/(frames|probes|\.sluice\.lock): cannot create( directory)? \(Read-only file system\)")


if INNER:
    main([inner_full_disk, inner_read_only])
else:
    main([test_output_directory_that_cannot_be_created, test_file_size_limit_is_a_clear_error,
          test_full_disk_in_a_private_tmpfs])
