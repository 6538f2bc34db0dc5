#!/usr/bin/env bash
# Side-by-side speed of PySPH's 2D dam break and sluice's mirror of it (bench/peer_pysph_dam_break.toml),
# both on one thread, run one after the other in one go. Not part of CI.
#
#   bash bench/peer_pysph.sh [END_TIME] [sluice run options...]
#       (default 0.5 s of simulated time; PySPH's own is 2.5 s; e.g. --set domain.pair_precision=single)
#
# Needs Debian's python3-pysph (apt-get install python3-pysph) and a release build (make build).
# Speed is particles x force evaluations / wall seconds; PySPH's PECIntegrator evaluates once per
# step, sluice's predictor-corrector twice, so the fair ratio is per evaluation.
set -euo pipefail
cd "$(dirname "$0")/.."
end=${1:-0.5}
shift || true
extra=("$@")
example=/usr/lib/python3/dist-packages/pysph/examples/dam_break_2d.py
[ -f "$example" ] || { echo "peer_pysph: $example not found; apt-get install python3-pysph" >&2; exit 1; }
sluice=${SLUICE:-build/release/sluice}  # SLUICE=path/to/sluice compares another build
[ -x "$sluice" ] || { echo "peer_pysph: $sluice not built; run make build" >&2; exit 1; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

OMP_NUM_THREADS=1 /usr/bin/python3 "$example" --tf "$end" -d "$work/pysph" --disable-output > "$work/pysph.txt" 2>&1
p_particles=$(awk '/Total:/ {print $2}' "$work/pysph.txt")
p_wall=$(awk '/Run took:/ {print $3}' "$work/pysph.txt")
p_evals=$(awk -F, '$3 == "acceleration_eval_0" {print $4}' "$work/pysph/profile_info.csv")

"$sluice" run bench/peer_pysph_dam_break.toml --set time.end="$end" --set output.interval="$end" \
  --threads 1 -q -o "$work/sluice" "${extra[@]}" > "$work/sluice.txt"
s_particles=$(awk '/particles/ {print $2; exit}' "$work/sluice.txt")
s_steps=$(awk '/steps/ {print $2; exit}' "$work/sluice.txt")
s_per_step=$(awk '/steps/ {gsub(/\(/, "", $3); print $3; exit}' "$work/sluice.txt")
s_wall=$(awk '/loop time/ {print $3; exit}' "$work/sluice.txt")

/usr/bin/python3 - "$end" "$p_particles" "$p_evals" "$p_wall" "$s_particles" "$s_steps" "$s_per_step" "$s_wall" <<'PY'
import sys
end, pp, pe, pw, sp, ss, sk, sw = sys.argv[1:]
pp, pe, pw, sp, ss, sk, sw = int(pp), int(pe), float(pw), int(sp), int(ss), int(sk), float(sw)
p_rate = pp * pe / pw
s_rate = sp * ss * sk / sw
print(f"2D dam break (PySPH dam_break_2d.py geometry), end time {end} s, one thread")
print(f"{'':8} {'particles':>10} {'evaluations':>12} {'wall [s]':>9} {'M particle-evals/s':>19}")
print(f"{'PySPH':8} {pp:>10} {pe:>12} {pw:>9.2f} {p_rate*1e-6:>19.2f}")
print(f"{'sluice':8} {sp:>10} {ss*sk:>12} {sw:>9.2f} {s_rate*1e-6:>19.2f}")
print(f"ratio (sluice / PySPH, per force evaluation): {s_rate/p_rate:.1f}x")
PY
