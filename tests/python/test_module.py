"""The Python module (`import sluice`): cases, stepping, the particles as numpy arrays, runs with
outputs, the coupling hooks, pictures, and the errors a Python user meets. Run by CTest with pytest;
the module's directory and the sluice program come from the environment (SLUICE_PYTHON_DIR,
SLUICE_BIN)."""

import os
import signal
import struct
import subprocess
import sys
import textwrap
import time

import numpy as np
import pytest

sys.path.insert(0, os.environ["SLUICE_PYTHON_DIR"])
import sluice  # noqa: E402

SLUICE = os.environ["SLUICE_BIN"]

# A coarse dam break: about 900 particles, a few hundred steps a second of wall time per 0.1 s.
COARSE = {"domain.dx": 0.4, "time.end": 0.4, "output.interval": 0.1}


def coarse(**more):
    return sluice.load_case("dam_break", overrides={**COARSE, **more})


# ---- cases -------------------------------------------------------------------------------------

def test_a_case_loads_from_a_builtin_name_a_file_and_a_dict(tmp_path):
    builtin = sluice.load_case("dam_break")
    assert builtin.name == "dam_break" and builtin.dimension == 2 and builtin.dx == 0.2
    path = tmp_path / "tank.toml"
    path.write_text('[case]\nname = "tank"\n[domain]\ndx = 0.05\n[tank]\nwidth = 1.0\nheight = 1.0\n'
                    '[[water]]\nmin = [0.0, 0.0]\nmax = [1.0, 0.5]\n[time]\nend = 0.1\n')
    from_file = sluice.load_case(path)
    assert from_file.name == "tank" and from_file.dx == 0.05
    from_dict = sluice.load_case({"case": {"name": "tank"}, "domain": {"dx": 0.05},
                                  "tank": {"width": 1.0, "height": 1.0},
                                  "water": [{"min": [0.0, 0.0], "max": [1.0, 0.5]}], "time": {"end": 0.1}})
    assert from_dict.name == "tank" and from_dict.end_time == 0.1
    assert set(sluice.cases()) >= {"dam_break", "floating_box", "dam_break_3d"}


def test_overrides_change_keys_as_set_does():
    c = sluice.load_case("dam_break", overrides={"time.end": 0.5, "domain.dx": 0.1, "physics.shifting": 0.0})
    assert c.end_time == 0.5 and c.dx == 0.1


def test_case_mistakes_raise_case_error_with_the_command_lines_message(tmp_path):
    with pytest.raises(sluice.CaseError, match="domain.dxx"):
        sluice.load_case("dam_break", overrides={"domain.dxx": 0.1})
    with pytest.raises(sluice.CaseError, match="domain.dx"):
        sluice.load_case("dam_break", overrides={"domain.dx": -1.0})
    with pytest.raises(sluice.CaseError, match="domain.dx"):
        sluice.load_case("dam_break", overrides={"domain.dx": "fine"})
    bad = tmp_path / "bad.toml"
    bad.write_text("[domain]\ndx = 0.1\n[tank]\nwidth = -3.0\n")
    with pytest.raises(sluice.CaseError) as e:
        sluice.load_case(bad)
    assert "bad.toml:4" in str(e.value) and "tank.width" in str(e.value)
    # The command line says the same.
    cli = subprocess.run([SLUICE, "run", str(bad), "-o", str(tmp_path / "o")], capture_output=True, text=True)
    assert cli.returncode == 2 and str(e.value) in cli.stderr
    with pytest.raises(sluice.CaseError, match="neither a built-in case"):
        sluice.load_case("no_such_case")
    with pytest.raises(TypeError):
        sluice.load_case(42)
    with pytest.raises(sluice.CaseError, match="object"):
        sluice.load_case("dam_break", overrides={"time.end": object()})
    assert issubclass(sluice.CaseError, ValueError)


# ---- stepping and the particles -----------------------------------------------------------------

def test_advance_to_lands_on_the_time_and_particles_are_numpy_in_id_order():
    sim = sluice.Simulation(coarse(), threads=1)
    assert sim.time == 0.0 and sim.step_count == 0 and sim.dimension == 2
    assert sim.advance_to(0.05) == 0.05 and sim.time == 0.05
    p = sim.particles()
    n = sim.particle_count
    assert {"x", "v", "rho", "p", "kind", "id"} <= set(p)
    assert p["x"].shape == (n, 2) and p["x"].dtype == np.float64
    assert p["v"].shape == (n, 2) and p["rho"].shape == (n,) and p["kind"].dtype == np.uint8
    assert np.array_equal(p["id"], np.arange(n, dtype=p["id"].dtype))
    assert np.all(np.isfinite(p["x"])) and sim.diagnostics()["time"] == 0.05
    # The arrays are copies: changing them changes nothing in the simulation.
    p["x"][:] = 0.0
    assert not np.all(sim.particles()["x"] == 0.0)
    assert sim.step(3) == 3 and sim.step_count > 0


def test_positions_after_n_steps_are_bit_for_bit_those_of_sluice_run(tmp_path):
    out = tmp_path / "cli"
    subprocess.run([SLUICE, "run", "dam_break", "-q", "--threads", "1", "-o", str(out), "--set", "domain.dx=0.4",
                    "--set", "time.end=0.4", "--set", "output.interval=0.1"], check=True, capture_output=True)
    run = sluice.open_run(out)
    last = run.frames[-1]
    sim = sluice.Simulation(coarse(), threads=1)
    sim.step(last["step"])
    assert sim.step_count == last["step"] and sim.time == last["t"]
    p = sim.particles()
    assert np.array_equal(p["x"], last["x"]) and np.array_equal(p["v"], last["v"])
    assert np.array_equal(p["rho"], last["rho"])


def test_two_threads_give_the_same_particles_as_one():
    one = sluice.Simulation(coarse(), threads=1)
    two = sluice.Simulation(coarse(), threads=2)
    one.advance_to(0.1)
    two.advance_to(0.1)
    assert np.array_equal(one.particles()["x"], two.particles()["x"])


# ---- runs with outputs --------------------------------------------------------------------------

def test_a_run_with_an_output_directory_writes_what_sluice_run_writes(tmp_path):
    sim = sluice.Simulation(coarse(), threads=1, output_dir=tmp_path / "py")
    result = sim.run(progress=False)
    assert result["time"] == pytest.approx(0.4) and result["frames_written"] == 5
    assert "finished" in result["summary"]
    subprocess.run([SLUICE, "run", "dam_break", "-q", "--threads", "1", "-o", str(tmp_path / "cli"), "--set",
                    "domain.dx=0.4", "--set", "time.end=0.4", "--set", "output.interval=0.1"], check=True)
    py_run, cli_run = sluice.open_run(tmp_path / "py"), sluice.open_run(tmp_path / "cli")
    assert len(py_run.frames) == len(cli_run.frames) == 5
    for a, b in zip(py_run.frames, cli_run.frames):
        assert a["t"] == b["t"] and np.array_equal(a["x"], b["x"])
    assert np.array_equal(py_run.diagnostics["step"], cli_run.diagnostics["step"])
    assert (tmp_path / "py" / "checkpoint.bin").is_file() and py_run.summary.startswith("sluice")
    assert py_run.frames.times.tolist() == pytest.approx([0.0, 0.1, 0.2, 0.3, 0.4])


def test_a_finished_run_opens_as_numpy_arrays(tmp_path):
    case = sluice.load_case("floating_box", overrides={"domain.dx": 0.04, "time.end": 0.2})
    sluice.Simulation(case, threads=1, output_dir=tmp_path).run(progress=False)
    run = sluice.open_run(tmp_path)
    assert "body" in run.frames[0]
    assert set(run.bodies) and all(len(t["time"]) > 1 for t in run.bodies.values())
    d = run.diagnostics
    assert d["time"][-1] == pytest.approx(0.2) and np.all(np.isfinite(d["total_energy"]))
    assert run.frames.at(0.1)["t"] == pytest.approx(0.1, abs=0.051)


def test_an_analysis_report_opens_as_tables(tmp_path):
    sluice.Simulation(coarse(**{"time.end": 1.0}), threads=1, output_dir=tmp_path / "run").run(progress=False)
    subprocess.run([SLUICE, "analyze", str(tmp_path / "run"), "-o", str(tmp_path / "report")], check=True,
                   capture_output=True)
    report = sluice.open_report(tmp_path / "report")
    waves, summary = report["waves"], report["summary"]
    assert waves["time"].dtype == np.float64 and waves["time"][-1] == pytest.approx(1.0)
    assert np.isnan(waves["front"][0])  # an empty value: the front had not formed
    assert summary["quantity"][0] == "tank width L" and summary["value"][0] == 20.0
    with pytest.raises(sluice.FormatError, match="no .csv tables"):
        sluice.open_report(tmp_path / "run" / "frames")


def test_callbacks_come_every_n_steps_and_every_interval_of_simulated_time():
    sim = sluice.Simulation(coarse(), threads=1)
    steps = []
    sim.run(until=0.1, callback=lambda s: steps.append(s.step_count), every_steps=5, progress=False)
    assert steps and all(b - a == 5 for a, b in zip(steps, steps[1:]))
    times = []
    sim.run(until=0.3, callback=lambda s: times.append(s.time), every=0.05, progress=False)
    # After the first step that reaches each multiple of 0.05 s from t = 0.1 s on.
    assert len(times) == 4 and all(t >= 0.1 + 0.05 * (k + 1) - 1e-12 for k, t in enumerate(times))
    assert sim.time == pytest.approx(0.3)


def test_a_callback_measures_something_during_a_run():
    sim = sluice.Simulation(coarse(), threads=1)
    front = []

    def measure(s):
        p = s.particles()
        water = p["kind"] == 0
        front.append(p["x"][water, 0].max())

    sim.run(until=0.3, callback=measure, every=0.1, progress=False)
    assert len(front) == 3 and front[0] < front[-1]  # the collapsing column's front advances


def test_other_python_threads_run_while_the_solver_steps():
    import threading

    sim = sluice.Simulation(sluice.load_case("dam_break", overrides={"domain.dx": 0.1, "time.end": 2.0}), threads=1)
    done = threading.Event()
    ticks = [0]

    def count():
        while not done.is_set():
            ticks[0] += 1
            time.sleep(0.001)

    counter = threading.Thread(target=count)
    counter.start()
    started = time.perf_counter()
    sim.step(400)  # one call: the lock is taken back only between steps
    seconds = time.perf_counter() - started
    done.set()
    counter.join()
    # A thread sleeping 1 ms a tick gets most of its ticks only if the solver lets go of the lock.
    assert ticks[0] > 0.3 * seconds / 0.001


def test_run_prints_a_progress_line_when_asked(capfd):
    sim = sluice.Simulation(coarse(), threads=1)
    sim.run(until=0.2, progress=True)
    err = capfd.readouterr().err
    assert "t = 0.200/0.200 s" in err and "ETA" in err and err.count("\r") >= 1


# ---- coupling hooks -----------------------------------------------------------------------------

def test_set_velocities_changes_the_waters_velocity():
    sim = sluice.Simulation(coarse(), threads=1)
    sim.step(2)
    p = sim.particles()
    water = p["id"][p["kind"] == 0][:10]
    v = np.tile([0.5, -0.25], (len(water), 1))
    assert sim.set_velocities(water, v) == len(water)
    after = sim.particles()
    assert np.array_equal(after["v"][water], v)
    sim.step(1)  # the next step starts from them
    assert np.all(np.isfinite(sim.particles()["v"]))


def test_a_body_force_adds_its_acceleration_to_the_water():
    plain = sluice.Simulation(coarse(), threads=1)
    pushed = sluice.Simulation(coarse(), threads=1)
    seen = []

    def push(x, t):
        seen.append((x.shape, t))
        return np.array([2.0, 0.0])

    pushed.set_body_force(push)
    plain.step(1)
    pushed.step(1)
    assert plain.dt == pushed.dt
    water = plain.particles()["kind"] == 0
    dv = pushed.particles()["v"][water] - plain.particles()["v"][water]
    # The step's velocity change gains a dt along x: exactly in the bulk, and to within the pressure's
    # response (the water moved by a dt^2 / 2 against the walls) on every particle of water.
    push = 2.0 * plain.dt
    assert np.median(dv[:, 0]) == pytest.approx(push, rel=1e-9)
    assert np.allclose(dv[:, 0], push, rtol=0.01) and np.all(np.abs(dv[:, 1]) < 0.01 * push)
    assert seen[0][0] == (int(water.sum()), 2) and seen[0][1] == 0.0
    # A field of position: an array of one row per particle of water.
    pushed.set_body_force(lambda x, t: np.where(x[:, :1] > 5.0, [[1.0, 0.0]], [[0.0, 0.0]]))
    pushed.step(1)
    pushed.set_body_force(None)
    pushed.step(1)


def test_errors_in_python_callbacks_reach_the_caller_with_their_own_type():
    sim = sluice.Simulation(coarse(), threads=1)

    def broken(x, t):
        raise ZeroDivisionError("the coupled code failed")

    sim.set_body_force(broken)
    with pytest.raises(ZeroDivisionError, match="the coupled code failed"):
        sim.step(1)
    sim2 = sluice.Simulation(coarse(), threads=1)
    sim2.set_body_force(lambda x, t: np.zeros((3, 7)))
    with pytest.raises(ValueError, match=r"shape \(3, 7\)"):
        sim2.step(1)
    sim3 = sluice.Simulation(coarse(), threads=1)
    sim3.set_body_force(lambda x, t: np.full(2, np.nan))
    with pytest.raises(sluice.RunFailure, match="not finite"):
        sim3.step(1)


# ---- bad input ----------------------------------------------------------------------------------

def test_bad_arrays_and_closed_simulations_raise_clear_errors(tmp_path):
    sim = sluice.Simulation(coarse(), threads=1)
    p = sim.particles()
    wall = p["id"][p["kind"] == 1][:1]
    with pytest.raises(ValueError, match="wall particle"):
        sim.set_velocities(wall, np.zeros((1, 2)))
    with pytest.raises(ValueError, match=r"expected shape \(2, 2\)"):
        sim.set_velocities([0, 1], np.zeros((2, 3)))
    with pytest.raises(ValueError, match="integer particle ids"):
        sim.set_velocities(np.array([0.5]), np.zeros((1, 2)))
    with pytest.raises(ValueError, match="no particle"):
        sim.set_velocities([10**8], np.zeros((1, 2)))
    with pytest.raises(ValueError, match="not finite"):
        sim.set_velocities([0], np.array([[np.nan, 0.0]]))
    with pytest.raises(TypeError, match="expected a function"):
        sim.set_body_force(3)
    with pytest.raises(ValueError, match="past the case's end"):
        sim.advance_to(5.0)
    with pytest.raises(ValueError, match="threads"):
        sluice.Simulation(coarse(), threads=0)
    sim.close()
    assert sim.closed
    with pytest.raises(RuntimeError, match="closed"):
        sim.step()
    with pytest.raises(RuntimeError, match="closed"):
        sim.particles()
    with pytest.raises(FileNotFoundError):
        sluice.open_run(tmp_path / "none")
    with pytest.raises(sluice.FormatError, match="not a sluice run"):
        sluice.open_run(tmp_path)
    (tmp_path / "frames").mkdir()
    (tmp_path / "frames" / "frame_000000.npz").write_bytes(b"not a zip")
    with pytest.raises(sluice.FormatError, match="not a sluice frame"):
        sluice.open_run(tmp_path).frames[0]


def test_an_unstable_run_raises_with_the_last_good_state_kept():
    case = sluice.load_case("dam_break", overrides={**COARSE, "time.dt": 0.05, "time.end": 2.0})
    sim = sluice.Simulation(case, threads=1)
    with pytest.raises(sluice.InstabilityError, match="unstable"):
        sim.advance_to(2.0)
    assert np.all(np.isfinite(sim.particles()["x"]))


def test_a_second_run_into_the_same_directory_is_refused(tmp_path):
    first = sluice.Simulation(coarse(), threads=1, output_dir=tmp_path)
    with pytest.raises(sluice.OutputError, match="in use"):
        sluice.Simulation(coarse(), threads=1, output_dir=tmp_path)
    first.close()
    sluice.Simulation(coarse(), threads=1, output_dir=tmp_path).close()


# ---- Ctrl-C, restart, pictures ------------------------------------------------------------

def test_ctrl_c_saves_the_state_and_raises_keyboard_interrupt_then_a_restart_continues(tmp_path):
    script = textwrap.dedent(f"""
        import sys
        sys.path.insert(0, {os.environ["SLUICE_PYTHON_DIR"]!r})
        import sluice
        case = sluice.load_case("dam_break", overrides={{"domain.dx": 0.2, "time.end": 30.0}})
        sim = sluice.Simulation(case, threads=1, output_dir={str(tmp_path)!r})
        print("started", flush=True)
        try:
            sim.run(progress=False)
        except KeyboardInterrupt:
            print("interrupted at", repr(sim.time), flush=True)
            sys.exit(130)
    """)
    child = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                             text=True)
    assert child.stdout.readline().strip() == "started"
    time.sleep(1.0)
    child.send_signal(signal.SIGINT)
    out, err = child.communicate(timeout=120)
    assert child.returncode == 130, err
    stopped_at = float(out.split()[-1])
    assert 0.0 < stopped_at < 30.0
    assert (tmp_path / "checkpoint.bin").is_file()
    assert "stopped on request" in (tmp_path / "summary.txt").read_text()
    sim = sluice.Simulation(restart=tmp_path / "checkpoint.bin", threads=1)
    assert sim.time == stopped_at
    sim.step(2)
    assert sim.time > stopped_at


def test_a_frame_draws_to_a_png_that_jupyter_shows(tmp_path):
    sim = sluice.Simulation(coarse(), threads=1, output_dir=tmp_path)
    sim.run(progress=False)
    for image in (sim.render("pressure"), sluice.render(tmp_path, "speed", time=0.2),
                  sluice.open_run(tmp_path).render("vx")):
        png = image._repr_png_()
        assert png[:8] == b"\x89PNG\r\n\x1a\n"
        width, height = struct.unpack(">II", png[16:24])
        assert width > 100 and height > 50
    with pytest.raises(sluice.RenderError, match="field"):
        sluice.render(tmp_path, "temperature")
