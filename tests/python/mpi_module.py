"""The Python module on several processes: run as `mpiexec -np 2 python3 mpi_module.py CLI_RUN OUT`
after `mpiexec -np 2 sluice run ... -o CLI_RUN` of the same case (test_python_mpi.sh). Each process
holds its region's particles; gathers are explicit; the run is the command line's on as many
processes, bit for bit."""
import os
import sys

import numpy as np
from mpi4py import MPI

sys.path.insert(0, os.environ["SLUICE_PYTHON_DIR"])
import sluice  # noqa: E402

cli_run, out = sys.argv[1], sys.argv[2]
world = MPI.COMM_WORLD
failures = []


def check(ok, what):
    if not ok:
        failures.append(what)


case = sluice.load_case("dam_break", overrides={"domain.dx": 0.2, "time.end": 0.2, "output.interval": 0.1})
sim = sluice.Simulation(case, threads=1, output_dir=out)
check(sim.processes == world.Get_size() == 2 and sim.rank == world.Get_rank(), "the processes")
mine = sim.particles()
everyone = world.allgather(mine["id"])
total = sim.particle_count  # collective
check(sum(len(ids) for ids in everyone) == total, "each particle on one process")
check(len(np.unique(np.concatenate(everyone))) == total, "no particle on two processes")
check(np.all(np.diff(mine["id"].astype(np.int64)) > 0), "this process's particles in id order")
check(0 < len(mine["id"]) < total, "the particles shared among the processes")

# Velocities of water particles wherever they are: each process sets those it holds.
p = sim.gather_particles()
ids = world.bcast(p["id"][p["kind"] == 0][:20] if p is not None else None)
check((p is None) == (sim.rank != 0), "the gather on the root alone")
set_here = sim.set_velocities(ids, np.zeros((len(ids), 2)))
check(world.allreduce(set_here) == len(ids), "every id set once")

result = sim.run(progress=False)
last = sim.gather_particles()
if sim.rank == 0:
    frame = sluice.open_run(cli_run).frames[-1]
    check(result["time"] == frame["t"], "the end time")
    # The same run as the command line's but for the 20 velocities set above: far from them (the
    # right half of the tank), the particles' positions agree to round-off after 0.2 s.
    check(last["x"].shape == frame["x"].shape, "all the particles gathered")
    right = frame["x"][:, 0] > 15.0
    check(np.allclose(last["x"][right], frame["x"][right], rtol=0, atol=1e-9), "the run")
sim.close()

# Without changes, the Python run on two processes is the command line's on two, bit for bit.
sim = sluice.Simulation(case, threads=1)
sim.advance_to(0.2)
last = sim.gather_particles()
if sim.rank == 0:
    frame = sluice.open_run(cli_run).frames[-1]
    check(np.array_equal(last["x"], frame["x"]) and np.array_equal(last["v"], frame["v"]),
          "bit for bit the command line's run on two processes")
# Ctrl-C reaching one process stops both after the same step, with the state saved, and raises
# KeyboardInterrupt on both.
import signal  # noqa: E402
import threading  # noqa: E402

long_case = sluice.load_case("dam_break", overrides={"domain.dx": 0.2, "time.end": 30.0})
sim = sluice.Simulation(long_case, threads=1, output_dir=out + "_stopped")
if sim.rank == 1:
    threading.Timer(1.0, lambda: os.kill(os.getpid(), signal.SIGINT)).start()
try:
    sim.run(progress=False)
    stopped_at = None
except KeyboardInterrupt:
    stopped_at = sim.time
times = world.allgather(stopped_at)
check(times[0] is not None and times[0] == times[1] and times[0] < 30.0, f"both stopped at one time: {times}")
if sim.rank == 0:
    check("stopped on request" in open(out + "_stopped/summary.txt").read(), "the summary of a stopped run")
    check(os.path.isfile(out + "_stopped/checkpoint.bin"), "the checkpoint of a stopped run")

failures = world.allgather(failures)
if world.Get_rank() == 0:
    bad = [f"process {r}: {what}" for r, fs in enumerate(failures) for what in fs]
    print("\n".join(bad) if bad else "mpi_module: every check passed on 2 processes")
    sys.exit(1 if bad else 0)
