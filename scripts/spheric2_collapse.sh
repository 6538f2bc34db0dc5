#!/usr/bin/env bash
# When does the water of SPHERIC test 2 reach the box, with the particle spacing refined? The 3D case
# at dx = 0.02 m (H/dx = 27.5) reads P1's impact about 0.03 s after the experiment's 0.394 s. Until the
# front reaches the box's face (x = 0.8245 m) the flow is two-dimensional, so a 2D section of the tank
# (scripts/spheric2_section_2d.toml) can be run at spacings the 3D case cannot afford. For each
# spacing this prints when the front reaches the face, and how far the level at H4 (in the reservoir)
# falls behind the experiment's record: the shift that best matches the two falls from their starting
# levels over 0.05 <= t <= 0.4 s, as `sluice validate` reports it for the 3D case. Not part of CI; dx = 0.0025 m takes a few minutes on one core.
#
#   bash scripts/spheric2_collapse.sh [DX ...] [-- sluice run options ...]
#       (default: 0.01 0.005 0.0025; e.g. -- --set fluid.sound_speed=66)
#
# Needs a release build (make build) and numpy (Debian python3-numpy).
set -euo pipefail
cd "$(dirname "$0")/.."
sluice=${SLUICE:-build/release/sluice}
[ -x "$sluice" ] || { echo "spheric2_collapse: $sluice not built; run make build" >&2; exit 1; }
spacings=()
while [ $# -gt 0 ] && [ "$1" != "--" ]; do spacings+=("$1"); shift; done
[ $# -gt 0 ] && shift
extra=("$@")
[ ${#spacings[@]} -gt 0 ] || spacings=(0.01 0.005 0.0025)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

echo "dx [m]   particles  front at x = 0.8245 m [s] (experiment's P1 impact: 0.394 s)  H4 behind the record [s] (RMS [mm])"
for dx in "${spacings[@]}"; do
  "$sluice" run scripts/spheric2_section_2d.toml --set domain.dx="$dx" "${extra[@]}" -q -o "$work/$dx" > "$work/$dx.txt"
  particles=$(awk '/particles/ {print $2; exit}' "$work/$dx.txt")
  /usr/bin/python3 - "$dx" "$particles" "$work/$dx/probes" data/validation/spheric2_kleefsman2005_exp.csv <<'PY'
import sys
import numpy as np

dx, particles, probes, record = sys.argv[1:5]
front = np.loadtxt(f"{probes}/front.csv", delimiter=",", skiprows=1)
reach = 1.992 - 0.8245  # the gate to the box's face
k = np.nonzero(front[:, 1] >= reach)[0]
if len(k) == 0 or k[0] == 0:
    arrival = "not reached"
else:
    (t0, d0), (t1, d1) = front[k[0] - 1, :2], front[k[0], :2]
    arrival = f"{t0 + (reach - d0) / (d1 - d0) * (t1 - t0):.4f}"
level = np.loadtxt(f"{probes}/H4.csv", delimiter=",", skiprows=1)
with open(record) as f:  # provenance lines (#), then the header, then the samples
    rows = [line for line in f if not line.startswith("#")][1:]
data = np.loadtxt(rows, delimiter=",")
t, h4 = data[:, 0], data[:, 6]
window = (t >= 0.05) & (t <= 0.4)
start = h4[t <= 0.01].mean()  # each level's fall from its start, as `sluice validate` compares them
best = (np.inf, 0.0)
for shift in np.arange(0.0, 0.1, 0.0005):
    if level[-1, 0] < 0.4 + shift:
        break
    sim = np.interp(t[window] + shift, level[:, 0], level[:, 1]) - level[0, 1]
    best = min(best, (np.sqrt(np.mean((h4[window] - start - sim) ** 2)), shift))
lag = f"{best[1]:.4f} ({best[0] * 1e3:.1f})" if np.isfinite(best[0]) else "run too short"
print(f"{dx:<8} {particles:>9}  {arrival:>40}  {lag:>30}")
PY
done
