"""Shared helpers for the output tests (test_outputs.py, test_restart.py, test_kill.py,
test_output_errors.py): a small case, running the sluice binary, and checks that read every file of a
run with real readers (numpy, meshio, csv, xml)."""

import argparse
import csv
import io
import os
import re
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET
import zlib

import meshio
import numpy as np

# A coarse dam break (the default case's geometry) with one probe of each type (and a gauge reading the
# kernel's surface, whose sums over processes the MPI tests compare): about 800 particles,
# a fraction of a second of wall time per simulated second.
CASE = """
[case]
name = "io_test"
description = "coarse dam break for the output tests"
[domain]
dx = 0.4
h_over_dx = 1.3
[physics]
# The default case's walls: still wall particles, whose frames' velocity is 0.
wall_boundary = "dynamic"
shifting = 0.0
[tank]
width = 20.0
height = 10.0
[time]
end = {end}
[output]
interval = {interval}
checkpoint_interval = {checkpoint_interval}
formats = {formats}

[[water]]
min = [0.0, 0.0]
max = [20.0, 2.0]
[[water]]
min = [0.0, 2.0]
max = [3.0, 5.0]

[[probe]]
name = "wall_pressure"
type = "pressure"
point = [19.6, 0.6]
[[probe]]
name = "gauge_mid"
type = "gauge"
point = [10.0, 0.0]
interval = 0.05
[[probe]]
name = "surface_mid"
type = "gauge"
point = [10.0, 0.0]
measure = "surface"
interval = 0.05
[[probe]]
name = "front"
type = "front"
point = [0.0, 0.0]
direction = [1.0, 0.0]
"""

NPZ_ARRAYS = {  # name -> (dtype, shape with N for the particle count)
    "t": ("<f8", ()),
    "step": ("<i8", ()),
    "dx": ("<f8", ()),
    "x": ("<f8", ("N", "D")),  # D: the run's dimension
    "v": ("<f8", ("N", "D")),
    "rho": ("<f8", ("N",)),
    "p": ("<f8", ("N",)),
    "kind": ("|u1", ("N",)),
    "id": ("<u4", ("N",)),
    "body": ("|u1", ("N",)),  # 0 water, 1 the tank, k + 2 the case's wall k
}

DIAGNOSTICS_COLUMNS = ["time", "step", "dt", "max_speed", "min_density", "max_density", "kinetic_energy",
                       "potential_energy", "total_energy", "total_mass", "leaks", "outflow", "min_particle_distance",
                       "wall_time"]

# Threads per run. One by default: tests run side by side (ctest -j) on shared cores, where OpenMP
# threads that wait for each other slow a run down many times. test_restart.py also uses two.
THREADS = 1

TEMP_NAME = re.compile(r"\.tmp\d+$")


class Failure(AssertionError):
    pass


def check(condition, message):
    if not condition:
        raise Failure(message)


def arguments(description):
    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("--sluice", required=True, help="path of the sluice binary")
    parser.add_argument("--workdir", required=True, help="scratch directory (emptied first)")
    args = parser.parse_args()
    shutil.rmtree(args.workdir, ignore_errors=True)
    os.makedirs(args.workdir)
    return args


def write_case(path, end=1.0, interval=0.1, checkpoint_interval=0.0, formats=("vtk", "npz")):
    text = CASE.format(end=end, interval=interval, checkpoint_interval=checkpoint_interval,
                       formats="[" + ", ".join(f'"{f}"' for f in formats) + "]")
    with open(path, "w") as f:
        f.write(text)
    return path


def run(sluice, *args, expect=0, threads=None, **kwargs):
    """Runs sluice quietly (with THREADS threads unless given); checks its exit status; returns the
    CompletedProcess."""
    command = [sluice, "run", "-q", "--threads", str(threads or THREADS), *args]
    r = subprocess.run(command, capture_output=True, text=True, timeout=600, **kwargs)
    if expect is not None and r.returncode != expect:
        raise Failure(f"{' '.join(command)}: exit status {r.returncode}, expected {expect}\n"
                      f"stdout:\n{r.stdout}\nstderr:\n{r.stderr}")
    return r


def final_files(directory):
    """Every file under a final name (not a temporary .tmpPID), relative to the directory."""
    out = []
    for root, _, names in os.walk(directory):
        for name in names:
            if not TEMP_NAME.search(name):
                out.append(os.path.relpath(os.path.join(root, name), directory))
    return sorted(out)


def temp_files(directory):
    return sorted(os.path.relpath(os.path.join(root, n), directory)
                  for root, _, names in os.walk(directory) for n in names if TEMP_NAME.search(n))


def load_npz(path, dimension=2):
    """numpy.load with no pickle and no custom code; checks names, dtypes and shapes (positions and
    velocities N x dimension)."""
    with np.load(path, allow_pickle=False) as data:
        arrays = {name: data[name] for name in data.files}
    check(sorted(arrays) == sorted(NPZ_ARRAYS), f"{path}: arrays {sorted(arrays)}")
    n = arrays["rho"].shape[0]
    for name, (dtype, shape) in NPZ_ARRAYS.items():
        a = arrays[name]
        check(a.dtype == np.dtype(dtype), f"{path}: {name} has dtype {a.dtype}, expected {dtype}")
        expected = tuple({"N": n, "D": dimension}.get(s, s) for s in shape)
        check(a.shape == expected, f"{path}: {name} has shape {a.shape}, expected {expected}")
    return arrays


def load_vtu(path):
    mesh = meshio.read(path)
    n = mesh.points.shape[0]
    check(len(mesh.cells) == 1 and mesh.cells[0].type == "vertex" and len(mesh.cells[0].data) == n,
          f"{path}: expected one vertex cell per point")
    check(sorted(mesh.point_data) == ["body", "density", "id", "kind", "pressure", "velocity"],
          f"{path}: point data {sorted(mesh.point_data)}")
    return mesh


def load_pvd(path):
    """[(time, file)] of a ParaView collection, times parsed from the text exactly."""
    root = ET.parse(path).getroot()
    check(root.tag == "VTKFile" and root.get("type") == "Collection", f"{path}: not a VTK collection")
    return [(float(d.get("timestep")), d.get("file")) for d in root.iter("DataSet")]


def load_csv(path, header=None):
    """Header and rows (floats) of a CSV file; every row complete."""
    with open(path, newline="") as f:
        text = f.read()
    check(text.endswith("\n"), f"{path}: does not end with a newline (cut off?)")
    rows = list(csv.reader(io.StringIO(text)))
    check(len(rows) >= 1, f"{path}: empty")
    if header is not None:
        check(rows[0] == header, f"{path}: header {rows[0]}, expected {header}")
    width = len(rows[0])
    values = []
    for k, row in enumerate(rows[1:]):
        check(len(row) == width, f"{path}: row {k + 1} has {len(row)} columns, expected {width}")
        values.append([float(x) for x in row])
    return rows[0], np.array(values).reshape(-1, width)


def check_checkpoint_file(path):
    """The checkpoint's signature and CRC-32 (of everything before the last 4 bytes)."""
    with open(path, "rb") as f:
        data = f.read()
    check(data[:8] == b"SLUICECK", f"{path}: no checkpoint signature")
    check(zlib.crc32(data[:-4]) == int.from_bytes(data[-4:], "little"), f"{path}: checksum mismatch")


def checkpoint_without_wall_time(data):
    """A checkpoint's bytes with its wall-time field and checksum cut out. Layout: signature (8),
    version (4), dimension (4), case length (8), case text, time, step, last dt, leaks, wall seconds
    (8 each), the rates carried (version 3), particles ..., CRC-32 (4)."""
    case_length = int.from_bytes(data[16:24], "little")
    wall = 24 + case_length + 32
    return data[:wall] + data[wall + 8:-4]


def check_outputs_readable(directory, dimension=2):
    """Every file under a final name in a run's directory is complete and readable by its reader.
    Returns the final file names."""
    names = final_files(directory)
    for name in names:
        path = os.path.join(directory, name)
        if name.endswith(".npz"):
            load_npz(path, dimension)
        elif name.endswith(".vtu"):
            load_vtu(path)
        elif name.endswith(".pvd"):
            for _, f in load_pvd(path):
                check(os.path.exists(os.path.join(directory, f)), f"{path}: lists {f}, which does not exist")
        elif name == "diagnostics.csv":
            load_csv(path, DIAGNOSTICS_COLUMNS)
        elif name.startswith("probes" + os.sep) and name.endswith(".csv"):
            load_csv(path)
        elif name == "checkpoint.bin":
            check_checkpoint_file(path)
        elif name == ".sluice.lock":
            pass  # the output directory's lock, left by a killed run (io/directory_lock.hpp)
        elif name == "summary.txt":
            with open(path) as f:
                check("output" in f.read(), f"{path}: incomplete summary")
        else:
            raise Failure(f"{path}: unexpected file")
    return names


def assert_same_outputs(a, b, what):
    """Two run directories hold the same files with the same bytes, except the wall time recorded in
    diagnostics.csv, the checkpoint and the summary."""
    names_a, names_b = final_files(a), final_files(b)
    check(names_a == names_b, f"{what}: different files:\n  {names_a}\n  {names_b}")
    compared = 0
    for name in names_a:
        if name == "summary.txt":
            continue
        with open(os.path.join(a, name), "rb") as fa, open(os.path.join(b, name), "rb") as fb:
            da, db = fa.read(), fb.read()
        if name == "diagnostics.csv":
            da = b"\n".join(line.rsplit(b",", 1)[0] for line in da.split(b"\n"))
            db = b"\n".join(line.rsplit(b",", 1)[0] for line in db.split(b"\n"))
        elif name == "checkpoint.bin":
            da, db = checkpoint_without_wall_time(da), checkpoint_without_wall_time(db)
        check(da == db, f"{what}: {name} differs")
        compared += 1
    return compared


def main(tests):
    """Runs each test function, prints PASS/FAIL lines; exit status 1 if any failed."""
    failed = 0
    for test in tests:
        try:
            test()
            print(f"PASS {test.__name__}", flush=True)
        except Exception as e:  # a Failure, or a reader's exception on a bad file
            failed += 1
            print(f"FAIL {test.__name__}: {type(e).__name__}: {e}", flush=True)
    print(f"{len(tests) - failed} of {len(tests)} passed")
    sys.exit(1 if failed else 0)
