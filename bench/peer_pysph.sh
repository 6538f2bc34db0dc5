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

# sluice runs once before PySPH and once after, so that a change of the shared machine's speed in
# between shows as a difference of the two.
run_sluice() {
  "$sluice" run bench/peer_pysph_dam_break.toml --set time.end="$end" --set output.interval="$end" \
    --threads 1 -q -o "$work/sluice_$1" "${extra[@]}" > "$work/sluice_$1.txt"
}
run_sluice before

OMP_NUM_THREADS=1 /usr/bin/python3 "$example" --tf "$end" -d "$work/pysph" --disable-output > "$work/pysph.txt" 2>&1
p_particles=$(awk '/Total:/ {print $2}' "$work/pysph.txt")
p_wall=$(awk '/Run took:/ {print $3}' "$work/pysph.txt")
p_evals=$(awk -F, '$3 == "acceleration_eval_0" {print $4}' "$work/pysph/profile_info.csv")
run_sluice after

s_particles=$(awk '/particles/ {print $2; exit}' "$work/sluice_before.txt")
s_steps=$(awk '/steps/ {print $2; exit}' "$work/sluice_before.txt")
s_per_step=$(awk '/steps/ {gsub(/\(/, "", $3); print $3; exit}' "$work/sluice_before.txt")
s_wall=$(awk '/loop time/ {print $3; exit}' "$work/sluice_before.txt")
s_wall2=$(awk '/loop time/ {print $3; exit}' "$work/sluice_after.txt")

/usr/bin/python3 - "$end" "$p_particles" "$p_evals" "$p_wall" "$s_particles" "$s_steps" "$s_per_step" "$s_wall" "$s_wall2" <<'PY'
import sys
end, pp, pe, pw, sp, ss, sk, sw, sw2 = sys.argv[1:]
pp, pe, pw, sp, ss, sk, sw, sw2 = int(pp), int(pe), float(pw), int(sp), int(ss), int(sk), float(sw), float(sw2)
p_rate = pp * pe / pw
s_rate, s_rate2 = sp * ss * sk / sw, sp * ss * sk / sw2
print(f"2D dam break (PySPH dam_break_2d.py geometry), end time {end} s, one thread")
print(f"{'':15} {'particles':>10} {'evaluations':>12} {'wall [s]':>9} {'M particle-evals/s':>19}")
print(f"{'sluice, before':15} {sp:>10} {ss*sk:>12} {sw:>9.2f} {s_rate*1e-6:>19.2f}")
print(f"{'PySPH':15} {pp:>10} {pe:>12} {pw:>9.2f} {p_rate*1e-6:>19.2f}")
print(f"{'sluice, after':15} {sp:>10} {ss*sk:>12} {sw2:>9.2f} {s_rate2*1e-6:>19.2f}")
print(f"ratio (sluice / PySPH, per force evaluation): {s_rate/p_rate:.1f}x and {s_rate2/p_rate:.1f}x "
      f"(sluice before and after PySPH; the machine's drift between them: {s_rate2/s_rate:.2f})")
PY
