# The Python half of the `sluice` module, run in the module's namespace when it is imported (the
# C++ half, module.cpp, defines Case, _Simulation, the errors and the renderer). Names starting with
# an underscore are not part of the interface.
import math as _math
import os as _os
import sys as _sys
import time as _time
from pathlib import Path as _Path


# ---------------------------------------------------------------------------------------------
# Cases


def _toml_value(value, key):
    """A Python value as TOML text (the syntax of `--set key=value`)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if _math.isnan(value):
            return "nan"
        if _math.isinf(value):
            return "inf" if value > 0 else "-inf"
        return repr(value)
    if isinstance(value, str):
        escaped = value.replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n").replace("\t", "\\t")
        return '"' + escaped + '"'
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_toml_value(v, key) for v in value) + "]"
    if isinstance(value, dict):
        return "{" + ", ".join(f"{_toml_key(k)} = {_toml_value(v, key)}" for k, v in value.items()) + "}"
    try:  # numpy scalars and arrays
        import numpy as np

        if isinstance(value, np.ndarray):
            return _toml_value(value.tolist(), key)
        if isinstance(value, np.generic):
            return _toml_value(value.item(), key)
    except ImportError:
        pass
    raise CaseError(f"{key}: a value of type {type(value).__name__} ({value!r}); expected a number, a string, "
                    "a boolean, a list or a dict")


def _toml_key(key):
    if not isinstance(key, str):
        raise CaseError(f"{key!r}: a case's keys are strings")
    return key if key and all(c.isalnum() or c in "_-" for c in key) else _toml_value(key, key)


def _toml_document(case):
    """A case given as a dict of tables ({"domain": {"dx": 0.02}, "water": [{...}]}) as TOML text."""
    lines = []
    for table, body in case.items():
        if isinstance(body, dict):
            lines.append(f"[{_toml_key(table)}]")
            lines += [f"{_toml_key(k)} = {_toml_value(v, f'{table}.{k}')}" for k, v in body.items()]
        elif isinstance(body, (list, tuple)) and body and all(isinstance(item, dict) for item in body):
            for item in body:
                lines.append(f"[[{_toml_key(table)}]]")
                lines += [f"{_toml_key(k)} = {_toml_value(v, f'{table}.{k}')}" for k, v in item.items()]
        else:
            lines.insert(0, f"{_toml_key(table)} = {_toml_value(body, table)}")
        lines.append("")
    return "\n".join(lines)


def load_case(source, overrides=None):
    """A checked case from a built-in name ("dam_break"), a case file's path, or a dict of the case
    file's tables ({"domain": {...}, "water": [{...}]}). `overrides` changes keys as `sluice run --set`
    does ({"time.end": 0.5, "water[0].max": [1, 2]}). Any mistake raises sluice.CaseError with the
    command line's message (file, line and column included)."""
    if isinstance(source, Case):
        case = source
    elif isinstance(source, dict):
        case = _parse_case(_toml_document(source), "the case dict")
    elif isinstance(source, (str, _os.PathLike)):
        case = _load_case(_os.fspath(source))
    else:
        raise TypeError(f"load_case: a {type(source).__name__}; expected a built-in case name, a path or a dict")
    if overrides:
        if not isinstance(overrides, dict):
            raise TypeError("overrides: expected a dict of case keys and values, such as {'time.end': 0.5}")
        case = case._with_overrides([f"{key}={_toml_value(value, key)}" for key, value in overrides.items()])
    return case


# ---------------------------------------------------------------------------------------------
# Simulations


def _in_notebook():
    return "ipykernel" in _sys.modules


class _ProgressLine:
    """The progress of a run on standard error, one line rewritten (a terminal or a notebook)."""

    def __init__(self, sim, end):
        self.sim, self.end, self.start_time, self.start_wall = sim, end, sim.time, _time.monotonic()
        self.steps0 = sim.step_count

    def update(self, last=False):
        t, wall = self.sim.time, _time.monotonic() - self.start_wall
        done = (t - self.start_time) / max(self.end - self.start_time, 1e-300)
        eta = wall * (1 - done) / done if done > 0 else float("nan")
        eta_text = f"{int(eta) // 60}:{int(eta) % 60:02d}" if _math.isfinite(eta) else "--:--"
        width = 24
        bar = "#" * int(width * min(done, 1.0))
        line = (f"\r[{bar:<{width}}] t = {t:.3f}/{self.end:.3f} s  step {self.sim.step_count}  "
                f"dt {self.sim.dt:.2e} s  ETA {eta_text}")
        _sys.stderr.write(line + ("\n" if last else ""))
        _sys.stderr.flush()


def _start_processes():
    """Under mpirun, MPI started by mpi4py (if nothing started it) and the processes shared by the
    simulations; returns how many processes there are."""
    if not _launched_by_mpi():
        return 1
    try:
        from mpi4py import MPI  # importing it starts MPI
    except ImportError:
        raise RuntimeError("this interpreter runs under mpirun: sluice shares a run among the processes through "
                           "mpi4py, which is not installed (Debian package python3-mpi4py)") from None
    _start_world()
    return MPI.COMM_WORLD.Get_size()


class Simulation(_Simulation):
    """A case's simulation, stepped from Python.

        sim = sluice.Simulation(sluice.load_case("dam_break"), threads=2)
        sim.advance_to(0.5)
        p = sim.particles()          # numpy copies: x, v, rho, p, kind, id, ... in id order

    `case`: a Case, or anything load_case takes. `output_dir`: write the frames, probes,
    diagnostics, checkpoints and summary there as `sluice run -o` does (none without it).
    `restart`: continue from a checkpoint file instead (no case then). `threads`: default all cores
    (shared among the processes under mpirun, where each process holds its region's particles);
    the steps use fewer while fewer are faster, as on a busy machine, with the same results. The steps are those of `sluice run` (they land on the frame and checkpoint times), so the
    particles after n steps are bit for bit the command line's.
    """

    def __init__(self, case=None, threads=None, output_dir=None, restart=None):
        if restart is not None and case is not None:
            raise ValueError("restart continues the case stored in the checkpoint; give no case with it")
        if restart is None and case is None:
            raise TypeError("Simulation: expected a case (sluice.load_case(...), a built-in name, a path or a dict)")
        if case is not None and not isinstance(case, Case):
            case = load_case(case)
        processes = _start_processes()
        if threads is None:
            threads = max(1, _default_threads() // processes)  # the cores shared among the processes
        if isinstance(threads, bool) or not isinstance(threads, int):
            raise TypeError(f"threads = {threads!r}: expected a whole number of threads")
        super().__init__(case, threads, None if output_dir is None else _Path(output_dir),
                         None if restart is None else _Path(restart))

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()
        return False

    def __repr__(self):
        if self.closed:
            return "<sluice.Simulation (closed)>"
        held = (f"{self.local_particle_count} particles on process {self.rank} of {self.processes}"
                if self.processes > 1 else f"{self.local_particle_count} particles")
        return (f"<sluice.Simulation '{self.case.name}': {held}, t = {self.time:.6g} s of {self.end_time:.6g} s, "
                f"step {self.step_count}>")

    def step(self, n=1):
        """Takes n steps (fewer at the case's end); returns how many were taken."""
        if isinstance(n, bool) or not isinstance(n, int) or n < 0:
            raise ValueError(f"step: n = {n!r}; expected a whole number of steps, 0 or more")
        return self._advance(n, _math.inf, _math.inf, _math.inf)

    def advance_to(self, t):
        """Steps until the time is t, the last step cut to end exactly on it."""
        t = float(t)
        if not _math.isfinite(t) or t < self.time:
            raise ValueError(f"advance_to: t = {t} s; expected a time from now (t = {self.time} s) on")
        if t > self.end_time:
            raise ValueError(f"advance_to: t = {t} s is past the case's end (time.end = {self.end_time} s); "
                             "load the case with a later end: load_case(..., overrides={'time.end': ...})")
        while self.time < t:
            if self._advance(1 << 62, t, t, _math.inf) == 0:
                break
        return self.time

    def run(self, until=None, callback=None, every=None, every_steps=None, progress=None):
        """Steps to the case's end (or `until`), calling callback(sim) every `every` seconds of
        simulated time (after the first step that reaches each multiple; steps are not cut) or every
        `every_steps` steps. With an output directory, the run ends as `sluice run` does (the last
        frame, a checkpoint, the summary) and its result (a dict) is returned. `progress`: a progress
        line on standard error (default: in a terminal or a notebook)."""
        end = self.end_time if until is None else float(until)
        if end > self.end_time:
            raise ValueError(f"run: until = {end} s is past the case's end (time.end = {self.end_time} s)")
        if every is not None and not (float(every) > 0):
            raise ValueError(f"run: every = {every!r}; expected a positive interval of simulated time (s)")
        if every_steps is not None and (isinstance(every_steps, bool) or not isinstance(every_steps, int)
                                        or every_steps < 1):
            raise ValueError(f"run: every_steps = {every_steps!r}; expected a whole number of steps, 1 or more")
        if callback is not None and not callable(callback):
            raise TypeError("run: callback must be a function of the simulation")
        if callback is not None and every is None and every_steps is None:
            every_steps = 1
        if progress is None:
            progress = _in_notebook() or _sys.stderr.isatty()
        line = _ProgressLine(self, end) if progress else None
        # The callback times k * every, each reached within rounding (6 * 0.05 = 0.30000000000000004).
        slack = 1e-9 * every if every else 0.0

        def next_after(t):
            k = _math.floor(t / every) + 1
            while (k - 1) * every - slack > t:
                k -= 1
            while k * every - slack <= t:
                k += 1
            return k * every

        next_time = next_after(self.time) if every else _math.inf
        steps_since = 0
        while self.time < end:
            stop_at = min(next_time - slack, end)
            most = every_steps - steps_since if every_steps else 1 << 62
            taken = self._advance(most, stop_at, end, 0.25 if line else _math.inf)
            steps_since += taken
            if line:
                line.update()
            reached = every and self.time >= next_time - slack
            due = (every_steps and steps_since >= every_steps) or reached
            if callback is not None and due:
                callback(self)
            if every_steps and steps_since >= every_steps:
                steps_since = 0
            if reached:
                next_time = next_after(self.time)
            if taken == 0 and not due and (self.stopped or self.time >= self.end_time):
                break
        if line:
            line.update(last=True)
        if self.writes_outputs and self.time >= self.end_time:
            return self.finish()
        return None

    def finish(self):
        """Ends the run: the last frame, a checkpoint and the summary when it writes outputs. Returns
        its result (time, steps, speed, the summary text, ...)."""
        return self._finish()

    def set_velocities(self, ids, velocities):
        """Sets the velocities (m/s, an N x dimension array) of the water's particles `ids`."""
        import numpy as np

        return self._set_velocities(np.asarray(ids), np.asarray(velocities))

    def render(self, field="speed", width=0, height=0, range=None):
        """A picture of the state now (sluice render's), shown inline in Jupyter."""
        import tempfile

        with tempfile.TemporaryDirectory(prefix="sluice-frame-") as tmp:
            self._write_state_frame(_Path(tmp))
            return Image(_render_png(_Path(tmp), field, None, width, height, range))


# ---------------------------------------------------------------------------------------------
# Pictures


class Image:
    """A PNG picture; Jupyter shows it inline."""

    def __init__(self, png):
        self.png = png

    def _repr_png_(self):
        return self.png

    def save(self, path):
        _Path(path).write_bytes(self.png)
        return path

    def __repr__(self):
        import struct

        width, height = struct.unpack(">II", self.png[16:24])
        return f"<sluice.Image {width} x {height} PNG>"


def render(run, field="speed", time=None, width=0, height=0, range=None):
    """A picture of a run's frame nearest `time` (the last by default) coloured by `field` (vx, vy,
    vz, speed, pressure, density), drawn as `sluice render` draws it."""
    path = run.path if isinstance(run, Run) else _Path(run)
    Run(path)  # the checks of a run directory
    return Image(_render_png(path, field, time, width, height, range))


# ---------------------------------------------------------------------------------------------
# Finished runs


class Table(dict):
    """A CSV file's columns as numpy arrays, by name (numbers as float64, an empty value NaN; other
    columns as strings); to_pandas() gives a DataFrame."""

    def __init__(self, path):
        import csv

        import numpy as np

        with open(path, newline="") as f:
            text = f.read()
        lines = [line for line in text.splitlines(keepends=True) if line.strip() and not line.startswith("#")]
        if not lines:
            raise FormatError(f"{path}: empty; expected a header line and rows")
        if not lines[-1].endswith("\n") and len(lines) > 1:
            lines = lines[:-1]  # a last line cut off by a kill
        rows = list(csv.reader(lines))
        names, rows = rows[0], rows[1:]
        for k, row in enumerate(rows):
            if len(row) != len(names):
                raise FormatError(f"{path}: row {k + 1} has {len(row)} values for {len(names)} columns")
        columns = {}
        for c, name in enumerate(names):
            values = [row[c] for row in rows]
            try:
                columns[name] = np.array([float(v) if v.strip() else _math.nan for v in values], dtype=float)
            except ValueError:
                columns[name] = np.array(values, dtype=str)
        super().__init__(columns)
        self.path = _Path(path)

    def to_pandas(self):
        import pandas

        return pandas.DataFrame(dict(self))

    def __repr__(self):
        n = len(next(iter(self.values()))) if self else 0
        return f"<sluice.Table {self.path.name}: {n} rows of {', '.join(self)}>"


class Frames:
    """A run's frames in order, each read when asked for: frames[k] is a dict of numpy arrays (x, v,
    rho, p, kind, id, ... and the scalars t, step, dx)."""

    def __init__(self, directory):
        self._files = sorted(_Path(directory).glob("frame_*.npz"))
        self._times = None

    def __len__(self):
        return len(self._files)

    def __getitem__(self, k):
        import numpy as np

        if isinstance(k, slice):
            return [self[i] for i in range(*k.indices(len(self)))]
        path = self._files[k]
        try:
            with np.load(path) as npz:
                out = {name: npz[name] for name in npz.files}
        except Exception as e:  # zipfile, numpy and OS errors alike: the file is not a frame
            raise FormatError(f"{path}: not a sluice frame ({e})") from None
        for name in ("t", "dx"):
            if name in out:
                out[name] = float(out[name])
        if "step" in out:
            out["step"] = int(out["step"])
        return out

    @property
    def times(self):
        """The frames' times (s), read from the frames' t arrays once."""
        import numpy as np

        if self._times is None:
            times = []
            for path in self._files:
                with np.load(path) as npz:
                    times.append(float(npz["t"]))
            self._times = np.array(times)
        return self._times

    def at(self, t):
        """The frame nearest time t."""
        import numpy as np

        return self[int(np.argmin(np.abs(self.times - t)))]


class Run:
    """A run directory written by `sluice run -o DIR` or Simulation(..., output_dir=DIR): its
    frames (read lazily), diagnostics, probes and bodies (Tables of numpy arrays) and summary."""

    def __init__(self, path):
        self.path = _Path(path)
        if not self.path.exists():
            raise FileNotFoundError(f"{self.path}: no such run directory")
        if not self.path.is_dir():
            raise NotADirectoryError(f"{self.path}: not a directory; expected a run's output directory")
        if not (self.path / "frames").is_dir() and not (self.path / "diagnostics.csv").is_file():
            raise FormatError(f"{self.path}: not a sluice run: it has neither frames/ nor diagnostics.csv (a run "
                              "writes them into its output directory, sluice run -o DIR)")

    def __repr__(self):
        return f"<sluice.Run {self.path}: {len(self.frames)} frames>"

    @property
    def frames(self):
        return Frames(self.path / "frames")

    @property
    def diagnostics(self):
        return Table(self.path / "diagnostics.csv")

    def _tables(self, sub):
        return {p.stem: Table(p) for p in sorted((self.path / sub).glob("*.csv"))}

    @property
    def probes(self):
        """The probes and gauges of the case, by name."""
        return self._tables("probes")

    @property
    def bodies(self):
        """The moving and floating walls' motion and loads, by name."""
        return self._tables("bodies")

    @property
    def summary(self):
        p = self.path / "summary.txt"
        return p.read_text() if p.is_file() else None

    def render(self, field="speed", time=None, width=0, height=0, range=None):
        return render(self, field, time, width, height, range)


def open_run(path):
    """A finished (or running) run's outputs: see Run."""
    return Run(path)


def open_report(path):
    """The tables an analysis or validation wrote (sluice analyze, validate, convergence -o DIR), by
    file name without .csv: {"checks": Table, "validation": Table, ...}."""
    path = _Path(path)
    if not path.is_dir():
        raise FileNotFoundError(f"{path}: no such report directory")
    tables = {p.stem: Table(p) for p in sorted(path.glob("*.csv"))}
    if not tables:
        raise FormatError(f"{path}: no .csv tables; expected the output directory of sluice analyze, validate or "
                          "convergence")
    return tables
