#!/usr/bin/env bash
# PySPH's own Buchner (2002) dam break (pysph/examples/dam_break/db_2d_buchner.py: WCSPH, H = 1 m,
# dx = 0.03 m, c0 = 10 sqrt(2gH), alpha = 0.1), measured the way `sluice validate` measures sluice:
# p* = p/(rho g H) at the far wall at 0.2H against t* = t sqrt(g/H), RMS against
# data/validation/buchner2002_p_wall_pysph.csv over 2 <= t* <= 7 and its three parts. Not part of CI.
#
#   bash scripts/peer_buchner_pysph.sh [OUTPUT_DIR]     (default /tmp/pysph_buchner; about 2 minutes)
#
# Needs Debian's python3-pysph. The pressure at the probe is PySPH's Shepard interpolation, over the
# fluid only (as sluice's probe) and over fluid and wall particles (as PySPH's own post-processing).
# If PySPH stops early (on this machine it has ended with a segmentation fault in its neighbour search
# near t = 2.2 s), the frames written so far are measured and the last t* is printed.
set -uo pipefail
cd "$(dirname "$0")/.."
out=${1:-/tmp/pysph_buchner}
example=/usr/lib/python3/dist-packages/pysph/examples/dam_break/db_2d_buchner.py
[ -f "$example" ] || { echo "peer_buchner_pysph: $example not found; apt-get install python3-pysph" >&2; exit 1; }
rm -rf "$out"
OMP_NUM_THREADS=1 /usr/bin/python3 "$example" -d "$out" > "$out.log" 2>&1
echo "PySPH exit status $? (log: $out.log)"
OMP_NUM_THREADS=1 /usr/bin/python3 - "$out" data/validation/buchner2002_p_wall_pysph.csv <<'PY'
import glob, sys
import numpy as np
from pysph.solver.utils import iter_output
from pysph.tools.interpolator import Interpolator
out, ref = sys.argv[1:]
files = sorted(glob.glob(out + '/db_2d_buchner_*.hdf5'), key=lambda f: int(f.rsplit('_', 1)[1].split('.')[0]))
H, g, rho = 1.0, 9.81, 1000.0
t, p_fluid, p_all = [], [], []
for info, fluid, wall in iter_output(files, 'fluid', 'boundary'):
    t.append(info['t'] * np.sqrt(g / H))
    p_fluid.append(Interpolator([fluid], x=[5.366 * H], y=[0.2 * H], method='shepard').interpolate('p').item() / (rho * g * H))
    p_all.append(Interpolator([fluid, wall], x=[5.366 * H], y=[0.2 * H], method='shepard').interpolate('p').item() / (rho * g * H))
t = np.array(t)
data = np.loadtxt(ref, delimiter=',', comments='#', skiprows=4)
ts, ps = data[:, 0], data[:, 1]
print(f"{len(t)} frames up to t* = {t[-1]:.2f}")
for name, p in (("fluid only", np.array(p_fluid)), ("fluid and walls", np.array(p_all))):
    parts = []
    for a, b in ((2, 7), (2, 3.5), (3.5, 5.5), (5.5, 7)):
        w = (ts >= a) & (ts <= min(b, t[-1]))
        e = np.interp(ts[w], t, p) - ps[w]
        parts.append(f"{a}-{b}: {np.sqrt(np.mean(e**2)):.3f}")
    impact = t[np.argmax(p >= 0.25)]
    print(f"{name:16} RMS dp*  " + "  ".join(parts) + f"  impact t* {impact:.3f}")
PY
