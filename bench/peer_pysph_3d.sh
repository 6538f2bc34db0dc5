#!/usr/bin/env bash
# Side-by-side speed in 3D: PySPH's SPHERIC test 2 example (dam_break_3d.py) and sluice's spheric2 at
# the same particle spacing, both on one thread, run one after the other in one go. Not part of CI.
#
#   bash bench/peer_pysph_3d.sh [DX] [END_TIME] [sluice run options...]
#       (default dx = 0.04 m, 0.05 s of simulated time; e.g. --set physics.wall_boundary=dynamic, the
#       wall treatment closest to PySPH's, whose wall particles integrate the continuity equation too)
#
# Needs Debian's python3-pysph (apt-get install python3-pysph) and a release build (make build).
# Speed is particles x force evaluations / wall seconds (the fair ratio per evaluation: PySPH's EPEC
# integrator and sluice's predictor-corrector both evaluate twice per step, and the two place their
# wall particles differently: PySPH one layer, sluice layers to 2h).
set -euo pipefail
cd "$(dirname "$0")/.."
dx=${1:-0.04}
end=${2:-0.05}
shift 2 || shift $#
extra=("$@")
example=/usr/lib/python3/dist-packages/pysph/examples/dam_break_3d.py
[ -f "$example" ] || { echo "peer_pysph_3d: $example not found; apt-get install python3-pysph" >&2; exit 1; }
sluice=${SLUICE:-build/release/sluice}  # SLUICE=path/to/sluice compares another build
[ -x "$sluice" ] || { echo "peer_pysph_3d: $sluice not built; run make build" >&2; exit 1; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# sluice runs once before PySPH and once after, so that a change of the shared machine's speed in
# between shows as a difference of the two.
run_sluice() {
  "$sluice" run spheric2 --set domain.dx="$dx" --set time.end="$end" --set output.interval="$end" \
    --threads 1 -q -o "$work/sluice_$1" "${extra[@]}" > "$work/sluice_$1.txt"
}
run_sluice before

OMP_NUM_THREADS=1 /usr/bin/python3 "$example" --dx "$dx" --tf "$end" -d "$work/pysph" --disable-output \
  > "$work/pysph.txt" 2>&1 || { cat "$work/pysph.txt" >&2; exit 1; }
p_particles=$(awk '/Total:/ {print $2}' "$work/pysph.txt")
p_wall=$(awk '/Run took:/ {print $3}' "$work/pysph.txt")
p_evals=$(awk -F, '$3 == "acceleration_eval_0" {print $4}' "$work/pysph/profile_info.csv")
run_sluice after

s_particles=$(awk '/particles/ {print $2; exit}' "$work/sluice_before.txt")
s_steps=$(awk '/steps/ {print $2; exit}' "$work/sluice_before.txt")
s_per_step=$(awk '/steps/ {gsub(/\(/, "", $3); print $3; exit}' "$work/sluice_before.txt")
s_wall=$(awk '/loop time/ {print $3; exit}' "$work/sluice_before.txt")
s_wall2=$(awk '/loop time/ {print $3; exit}' "$work/sluice_after.txt")
s_target=$(awk '/pair loop/ {print $3; exit}' "$work/sluice_before.txt")

/usr/bin/python3 - "$dx" "$end" "$p_particles" "$p_evals" "$p_wall" "$s_particles" "$s_steps" "$s_per_step" "$s_wall" "$s_wall2" "$s_target" "${extra[*]:-}" <<'PY'
import sys
dx, end, pp, pe, pw, sp, ss, sk, sw, sw2, target, options = sys.argv[1:]
pp, pe, pw, sp, ss, sk, sw, sw2 = int(pp), int(pe), float(pw), int(sp), int(ss), int(sk), float(sw), float(sw2)
p_rate = pp * pe / pw
s_rate, s_rate2 = sp * ss * sk / sw, sp * ss * sk / sw2
print(f"3D dam break (SPHERIC test 2), dx = {dx} m, end time {end} s, one thread; sluice's pair loop: {target}")
print(f"sluice: the spheric2 case{' with ' + options if options else ''}")
print(f"{'':15} {'particles':>10} {'evaluations':>12} {'wall [s]':>9} {'M particle-evals/s':>19}")
print(f"{'sluice, before':15} {sp:>10} {ss*sk:>12} {sw:>9.2f} {s_rate*1e-6:>19.3f}")
print(f"{'PySPH':15} {pp:>10} {pe:>12} {pw:>9.2f} {p_rate*1e-6:>19.3f}")
print(f"{'sluice, after':15} {sp:>10} {ss*sk:>12} {sw2:>9.2f} {s_rate2*1e-6:>19.3f}")
print(f"ratio (sluice / PySPH, per force evaluation): {s_rate/p_rate:.1f}x and {s_rate2/p_rate:.1f}x "
      f"(sluice before and after PySPH; the machine's drift between them: {s_rate2/s_rate:.2f})")
PY
