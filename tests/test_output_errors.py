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
    expect_error("/proc/self", r"/proc/self/(frames|probes): cannot create directory \(")


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
    small = os.path.join(W, "small")
    os.makedirs(small)
    if subprocess.run(["mount", "-t", "tmpfs", "-o", "size=600k", "tmpfs", small], capture_output=True).returncode:
        sys.exit(77)
    d = os.path.join(small, "out")
    r = expect_error(d, "No space left on device")
    check(r.stderr.startswith(f"sluice: error: {d}/"), f"the message does not name the file:\n{r.stderr}")
    names = check_outputs_readable(d)
    frames = [n for n in names if n.endswith(".npz")]
    check(len(frames) >= 2, f"expected the failure mid-run, after some frames: {names}")
    check(temp_files(d) == [], f"temporary files left: {temp_files(d)}")
    print(f"disk full after {len(frames)} frames: {r.stderr.strip()}")


def inner_read_only():
    ro = os.path.join(W, "read_only")
    os.makedirs(ro)
    if subprocess.run(["mount", "-t", "tmpfs", "-o", "ro,size=100k", "tmpfs", ro], capture_output=True).returncode:
        sys.exit(77)
    expect_error(ro, rf"{ro}/(frames|probes): cannot create directory \(Read-only file system\)")


if INNER:
    main([inner_full_disk, inner_read_only])
else:
    main([test_output_directory_that_cannot_be_created, test_file_size_limit_is_a_clear_error,
          test_full_disk_in_a_private_tmpfs])
