#!/usr/bin/python3
"""A run's outputs read back by real readers: every NumPy frame with numpy.load (names, dtypes, shapes,
values consistent with the equation of state and with diagnostics.csv), every .vtu with meshio (the
same values as the .npz), the .pvd collection (each frame with its time), probes/*.csv, and
output.formats choosing what is written."""

import os

import numpy as np

from io_common import (DIAGNOSTICS_COLUMNS, arguments, check, check_outputs_readable, load_csv, load_npz,
                       load_pvd, load_vtu, main, run, write_case)

args = arguments(__doc__)
RHO0, C0, GAMMA, G = 1000.0, 20.0, 7.0, 9.81  # the case's fluid (the defaults)
END, INTERVAL = 0.35, 0.1                     # frames at 0, 0.1, 0.2, 0.3 and the end 0.35

case = write_case(os.path.join(args.workdir, "case.toml"), end=END, interval=INTERVAL)
both = os.path.join(args.workdir, "both")
run(args.sluice, case, "-o", both)
frame_paths = sorted(os.path.join(both, "frames", f) for f in os.listdir(os.path.join(both, "frames")))
frames = [load_npz(p) for p in frame_paths if p.endswith(".npz")]


def test_every_file_is_readable_and_expected():
    names = check_outputs_readable(both)
    expected = sorted(
        [f"frames/frame_{k:06}.{ext}" for k in range(5) for ext in ("npz", "vtu")] +
        ["io_test.pvd", "diagnostics.csv", "checkpoint.bin", "summary.txt",
         "probes/wall_pressure.csv", "probes/gauge_mid.csv", "probes/surface_mid.csv", "probes/front.csv"])
    check(names == expected, f"files {names}, expected {expected}")


def test_npz_frames_have_consistent_values():
    times = [float(f["t"]) for f in frames]
    check(times == [0.0, 0.1, 0.2, 3 * 0.1, END], f"frame times {times}")
    steps = [int(f["step"]) for f in frames]
    check(steps[0] == 0 and all(b > a for a, b in zip(steps, steps[1:])), f"steps {steps}")
    first = frames[0]
    n = first["rho"].shape[0]
    walls = first["kind"] == 1
    check(0 < walls.sum() < n, "expected both fluid and wall particles")
    B = RHO0 * C0 ** 2 / GAMMA
    for f in frames:
        check(float(f["dx"]) == 0.4, "dx")
        check(f["rho"].shape[0] == n, "particle count changed")
        check(np.array_equal(f["id"], np.arange(n, dtype=np.uint32)), "rows are not in id order")
        check(set(np.unique(f["kind"])) <= {0, 1}, "kind outside {0, 1}")
        check(np.array_equal(f["kind"], first["kind"]), "kinds changed")
        check(np.all(np.isfinite(f["x"])) and np.all(np.isfinite(f["v"])), "non-finite state")
        # Pressure is the Tait equation of state of the density.
        tait = B * ((f["rho"] / RHO0) ** GAMMA - 1.0)
        check(np.allclose(f["p"], tait, rtol=1e-12, atol=1e-9), "p is not Tait(rho)")
        # Wall particles do not move; fluid stays in the tank.
        check(np.array_equal(f["x"][walls], first["x"][walls]), "wall particles moved")
        check(np.array_equal(f["v"][walls], np.zeros_like(f["v"][walls])), "wall particles have velocity")
        fluid = f["x"][~walls]
        check(fluid[:, 0].min() > 0 and fluid[:, 0].max() < 20 and fluid[:, 1].min() > 0, "fluid outside tank")
    check(not np.array_equal(frames[-1]["x"], first["x"]), "nothing moved")


def test_vtu_point_data_equals_the_npz_arrays():
    for npz_path in (p for p in frame_paths if p.endswith(".npz")):
        f = load_npz(npz_path)
        mesh = load_vtu(npz_path[:-4] + ".vtu")
        pd = {k: np.asarray(v) for k, v in mesh.point_data.items()}
        check(mesh.points.shape == (f["x"].shape[0], 3), f"{npz_path}: points {mesh.points.shape}")
        check(np.array_equal(mesh.points[:, :2], f["x"]) and not mesh.points[:, 2].any(), "positions differ")
        check(pd["velocity"].shape == (f["x"].shape[0], 3), "velocity is not a 3-vector per point")
        check(np.array_equal(pd["velocity"][:, :2], f["v"]) and not pd["velocity"][:, 2].any(), "velocity differs")
        for vtk_name, npz_name in (("density", "rho"), ("pressure", "p"), ("kind", "kind"), ("id", "id")):
            check(pd[vtk_name].shape == f[npz_name].shape, f"{vtk_name}: shape {pd[vtk_name].shape}")
            check(pd[vtk_name].dtype == f[npz_name].dtype, f"{vtk_name}: dtype {pd[vtk_name].dtype}")
            check(np.array_equal(pd[vtk_name], f[npz_name]), f"{npz_path}: {vtk_name} differs from {npz_name}")
        check(float(np.asarray(mesh.field_data["TimeValue"]).ravel()[0]) == float(f["t"]), "TimeValue")


def test_pvd_lists_each_frame_with_its_time():
    entries = load_pvd(os.path.join(both, "io_test.pvd"))
    check([f for _, f in entries] == [f"frames/frame_{k:06}.vtu" for k in range(5)], f"pvd files {entries}")
    check([t for t, _ in entries] == [float(f["t"]) for f in frames], f"pvd times {entries}")


def test_diagnostics_has_one_row_per_frame_matching_the_frames():
    header, rows = load_csv(os.path.join(both, "diagnostics.csv"), DIAGNOSTICS_COLUMNS)
    col = {name: k for k, name in enumerate(header)}
    check(rows.shape[0] == len(frames), f"{rows.shape[0]} rows for {len(frames)} frames")
    m = RHO0 * 0.4 * 0.4  # particle mass rho0 dx^2
    for row, f in zip(rows, frames):
        fluid = f["kind"] == 0
        check(row[col["time"]] == float(f["t"]) and row[col["step"]] == int(f["step"]), "time/step")
        speed = np.hypot(f["v"][fluid, 0], f["v"][fluid, 1])
        check(np.isclose(row[col["max_speed"]], speed.max(), rtol=1e-12, atol=0), "max_speed")
        check(row[col["min_density"]] == f["rho"].min() and row[col["max_density"]] == f["rho"].max(), "density")
        check(np.isclose(row[col["kinetic_energy"]], 0.5 * m * (speed ** 2).sum(), rtol=1e-9, atol=1e-9),
              "kinetic energy")
        check(np.isclose(row[col["potential_energy"]], m * G * f["x"][fluid, 1].sum(), rtol=1e-9), "potential")
        check(np.isclose(row[col["total_energy"]], row[col["kinetic_energy"]] + row[col["potential_energy"]],
                         rtol=1e-12), "total energy")
        check(np.isclose(row[col["total_mass"]], m * fluid.sum(), rtol=1e-12), "total mass")
        check(row[col["leaks"]] >= 0 and row[col["leaks"]] == int(row[col["leaks"]]), "leaks")
        if row[col["step"]] > 0:
            check(0 < row[col["dt"]] < 0.01, "dt")
    check(np.all(np.diff(rows[:, col["wall_time"]]) >= 0), "wall time goes backwards")


def test_probe_csvs():
    _, p = load_csv(os.path.join(both, "probes", "wall_pressure.csv"), ["time", "pressure", "neighbours"])
    _, g = load_csv(os.path.join(both, "probes", "gauge_mid.csv"), ["time", "height"])
    _, fr = load_csv(os.path.join(both, "probes", "front.csv"), ["time", "distance", "x", "y"])
    steps = int(frames[-1]["step"])
    check(p.shape[0] == steps + 1 and fr.shape[0] == steps + 1, "every-step probes: one row per step and t = 0")
    check(p[0, 0] == 0.0 and p[-1, 0] == END, "probe times")
    # Gauge at interval 0.05: one row at or just after each multiple of 0.05 s.
    check(g.shape[0] == 8, f"gauge rows {g.shape[0]}")
    check(np.all(g[:, 0] >= 0.05 * np.arange(8) - 1e-12) and np.all(g[:, 0] < 0.05 * np.arange(8) + 0.01),
          f"gauge times {g[:, 0]}")
    check(abs(g[0, 1] - 2.0) < 1e-9, f"gauge at t = 0 reads {g[0, 1]}, expected the 2 m layer")
    # The front starts at the column's right edge and advances.
    check(abs(fr[0, 1] - (20.0 - 0.2)) < 1e-9, f"front at t = 0: {fr[0, 1]}")
    check(p[0, 1] > 0.5 * RHO0 * G * 1.4, f"wall pressure at t = 0: {p[0, 1]}")


def test_formats_select_what_is_written():
    only_npz = os.path.join(args.workdir, "only_npz")
    run(args.sluice, case, "-o", only_npz, "--set", 'output.formats=["npz"]')
    names = check_outputs_readable(only_npz)
    check(not any(n.endswith((".vtu", ".pvd")) for n in names), f"npz only, but wrote {names}")
    check(sum(n.endswith(".npz") for n in names) == 5, f"npz frames {names}")
    only_vtk = os.path.join(args.workdir, "only_vtk")
    run(args.sluice, case, "-o", only_vtk, "--set", 'output.formats=["vtk"]')
    names = check_outputs_readable(only_vtk)
    check(not any(n.endswith(".npz") for n in names), f"vtk only, but wrote {names}")
    check(sum(n.endswith(".vtu") for n in names) == 5 and "io_test.pvd" in names, f"vtk frames {names}")
    # Same solver, same frames: the .vtu files are identical whichever formats are on.
    for k in range(5):
        with open(os.path.join(only_vtk, f"frames/frame_{k:06}.vtu"), "rb") as a, \
                open(os.path.join(both, f"frames/frame_{k:06}.vtu"), "rb") as b:
            check(a.read() == b.read(), f"frame {k} differs between runs")


def test_a_fresh_run_replaces_the_previous_outputs():
    again = os.path.join(args.workdir, "again")
    run(args.sluice, case, "-o", again)
    run(args.sluice, case, "-o", again, "--set", "time.end=0.15")
    names = check_outputs_readable(again)
    check(sum(n.endswith(".npz") for n in names) == 3, f"stale frames of the longer run remain: {names}")
    check(len(load_pvd(os.path.join(again, "io_test.pvd"))) == 3, "pvd")


main([test_every_file_is_readable_and_expected, test_npz_frames_have_consistent_values,
      test_vtu_point_data_equals_the_npz_arrays, test_pvd_lists_each_frame_with_its_time,
      test_diagnostics_has_one_row_per_frame_matching_the_frames, test_probe_csvs,
      test_formats_select_what_is_written, test_a_fresh_run_replaces_the_previous_outputs])
