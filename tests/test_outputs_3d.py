#!/usr/bin/python3
"""A 3D run's outputs read back by real readers: the NumPy frames with numpy.load (x and v N x 3), the
.vtu files with meshio (points and velocity equal to the .npz arrays, all three components), the .pvd
collection, the probe CSVs; the water stays at rest; a restart from a checkpoint continues bit for bit."""

import os

import numpy as np

from io_common import arguments, check, check_outputs_readable, load_csv, load_npz, load_pvd, load_vtu, main, run

args = arguments(__doc__)
W = args.workdir
END = 0.3
SETTINGS = ["--set", f"time.end={END}", "--set", "output.interval=0.1", "--set", "output.checkpoint_interval=0.1"]
out = os.path.join(W, "still_water_3d")
run(args.sluice, "still_water_3d", "-o", out, *SETTINGS)
frame_names = sorted(f for f in os.listdir(os.path.join(out, "frames")))
frames = [load_npz(os.path.join(out, "frames", f), dimension=3) for f in frame_names if f.endswith(".npz")]


def test_every_file_is_readable_and_expected():
    names = check_outputs_readable(out, dimension=3)
    expected = sorted([f"frames/frame_{k:06}.{ext}" for k in range(4) for ext in ("npz", "vtu")] +
                      ["still_water_3d.pvd", "diagnostics.csv", "checkpoint.bin", "summary.txt",
                       "probes/floor.csv", "probes/level.csv"])
    check(names == expected, f"files {names}, expected {expected}")


def squeezed_height(depth, column=0.5, c0=20.0, gamma=7.0, g=9.81):
    """Where a particle `depth` metres (of uncompressed water) below the surface of a `column` m deep
    column ends up above the floor once the column is squeezed to the Tait density of the weight above:
    the height of the water below it, integral of rho0 / rho over its mass (case hydrostatic_squeeze)."""
    stiffness = 1000.0 * c0 * c0 / gamma
    s = np.linspace(depth, column, 200001)  # uncompressed depth of the water below
    ratio = (1.0 + 1000.0 * g * s / stiffness) ** (-1.0 / gamma)
    return float(np.sum(0.5 * (ratio[1:] + ratio[:-1]) * np.diff(s)))


def test_npz_frames_are_three_dimensional_and_at_rest():
    first = frames[0]
    walls = first["kind"] == 1
    fluid = ~walls
    # The tank 0.6 x 0.4 x 0.8 m with its walls around it; the water 0.6 x 0.4 x 0.5 m at dx = 0.05 m.
    check(fluid.sum() == 12 * 8 * 10, f"{fluid.sum()} fluid particles")
    x = first["x"]
    # Squeezed to hydrostatic density (the case's hydrostatic_squeeze): columns sit on the floor, each
    # particle as high as the compressed water below it.
    low, high = x[fluid].min(axis=0), x[fluid].max(axis=0)
    check(np.allclose(low, [0.025, 0.025, squeezed_height(0.475)], rtol=0, atol=1e-7) and
          np.allclose(high, [0.575, 0.375, squeezed_height(0.025)], rtol=0, atol=1e-7),
          f"water region {low} .. {high}")
    for f in frames:
        check(np.array_equal(f["x"][walls], x[walls]), "wall particles moved")
        check(np.abs(f["v"][fluid]).max() < 0.02 * np.sqrt(9.81 * 0.5), "the water is not at rest")
        check(np.abs(f["x"][fluid] - x[fluid]).max() < 0.1 * 0.05, "fluid particles wandered")


def test_vtu_points_and_velocity_equal_the_npz_arrays():
    for f, name in zip(frames, (n for n in frame_names if n.endswith(".npz"))):
        mesh = load_vtu(os.path.join(out, "frames", name[:-4] + ".vtu"))
        check(mesh.points.shape == f["x"].shape, f"points {mesh.points.shape}")
        check(np.array_equal(mesh.points, f["x"]), "positions differ")
        check(np.array_equal(np.asarray(mesh.point_data["velocity"]), f["v"]), "velocities differ")
        check(np.array_equal(np.asarray(mesh.point_data["pressure"]), f["p"]), "pressures differ")


def test_pvd_and_probes():
    entries = load_pvd(os.path.join(out, "still_water_3d.pvd"))
    check([t for t, _ in entries] == [float(f["t"]) for f in frames], f"pvd times {entries}")
    _, floor = load_csv(os.path.join(out, "probes", "floor.csv"), ["time", "pressure", "neighbours"])
    _, level = load_csv(os.path.join(out, "probes", "level.csv"), ["time", "height"])
    # The floor probe 0.065 m above the floor, under 0.435 m of water; the level starts at the top of the
    # squeezed column, 3 mm below 0.5 m.
    expected = 1000.0 * 9.81 * 0.435
    top = squeezed_height(0.0)
    check(np.all(np.abs(floor[:, 1] - expected) < 0.05 * expected), f"floor pressure {floor[[0, -1], 1]}")
    check(np.all(floor[:, 2] > 30), "floor probe with few neighbours")
    check(abs(level[0, 1] - top) < 2e-4 and np.all(np.abs(level[:, 1] - top) < 0.02),
          f"level {level[[0, -1], 1]}, squeezed column {top}")


def test_restart_continues_bit_for_bit():
    half = os.path.join(W, "half")
    run(args.sluice, "still_water_3d", "-o", half, *SETTINGS, "--set", "time.end=0.2")
    run(args.sluice, "--restart", os.path.join(half, "checkpoint.bin"), "--set", f"time.end={END}")
    for k in range(4):
        with open(os.path.join(out, f"frames/frame_{k:06}.npz"), "rb") as a, \
                open(os.path.join(half, f"frames/frame_{k:06}.npz"), "rb") as b:
            check(a.read() == b.read(), f"frame {k} differs after the restart")


if __name__ == "__main__":
    main([test_every_file_is_readable_and_expected, test_npz_frames_are_three_dimensional_and_at_rest,
          test_vtu_points_and_velocity_equal_the_npz_arrays, test_pvd_and_probes, test_restart_continues_bit_for_bit])
