"""The default dam break, scripted: run it with a callback that follows the collapsing column's
height at the left wall, write its outputs as `sluice run` does, then open the run and plot its
energy.

    PYTHONPATH=build/release/python python3 examples/python/dam_break.py [OUTPUT_DIR]
"""
import sys

import matplotlib

matplotlib.use("Agg")  # files, no window
import matplotlib.pyplot as plt
import numpy as np

import sluice

out = sys.argv[1] if len(sys.argv) > 1 else "out/dam_break_py"

# The default case, coarser and shorter: about 3,500 particles, 2 s of flow.
case = sluice.load_case("dam_break", overrides={"domain.dx": 0.2, "time.end": 2.0, "output.interval": 0.1})
sim = sluice.Simulation(case, threads=2, output_dir=out)

column = []  # (t, height): the top of the water within 0.5 m of the left wall


def follow_column(s):
    p = s.particles()
    near_wall = (p["kind"] == 0) & (p["x"][:, 0] < 0.5)
    column.append((s.time, p["x"][near_wall, 1].max() + case.dx / 2))


follow_column(sim)  # at t = 0
result = sim.run(callback=follow_column, every=0.1)
print(result["summary"])
t, height = np.array(column).T
print(f"the column at the left wall fell from {height[0]:.2f} m to {height[-1]:.2f} m in {t[-1]:.1f} s")

run = sluice.open_run(out)
d = run.diagnostics
fig, (a, b) = plt.subplots(1, 2, figsize=(9, 3.2))
a.plot(t, height, "o-")
a.set(xlabel="t (s)", ylabel="height (m)", title="water at the left wall")
a.set_xlim(0, 2)
b.plot(d["time"], d["kinetic_energy"] / 1e3, label="kinetic")
b.plot(d["time"], (d["potential_energy"] - d["potential_energy"][0]) / 1e3, label="potential - initial")
b.set(xlabel="t (s)", ylabel="energy (kJ/m)", title="energy")
b.legend()
fig.tight_layout()
fig.savefig(f"{out}/column_and_energy.png", dpi=100)
run.render("speed").save(f"{out}/last_frame.png")
print(f"wrote {out}/column_and_energy.png and {out}/last_frame.png")
