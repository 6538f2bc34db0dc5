# Sourced by bench/peer_pysph.sh and bench/peer_pysph_3d.sh: the table of one side-by-side run.
#
#   peer_report WORK DIGITS TITLE...
#
# WORK holds PySPH's log (pysph.txt) and profile (pysph/profile_info.csv) and sluice's two summaries
# (sluice_before.txt, sluice_after.txt); DIGITS is how many decimals the rates get; each TITLE is a
# line printed above the table.
#
# Three ratios, because the two codes differ in what a particle and a step are:
# - per particle and force evaluation, all particles counted (the speed issue's measure);
# - per fluid particle and force evaluation: sluice fills its walls with layers to the kernel's
#   support and skips wall-wall pairs, PySPH's examples hold fewer wall particles per fluid particle,
#   so counting the wall particles flatters the code with more of them;
# - per fluid particle over the same simulated time (what a user waits for): each code's own time
#   step and evaluations per step count as well.
peer_report() {
  local work=$1 digits=$2
  shift 2
  local p_particles p_fluid p_wall p_evals s_particles s_fluid s_steps s_per_step s_wall s_wall2
  p_particles=$(awk '/Total:/ {print $2}' "$work/pysph.txt")
  p_fluid=$(awk '$1 == "fluid:" {print $2; exit}' "$work/pysph.txt")
  p_wall=$(awk '/Run took:/ {print $3}' "$work/pysph.txt")
  p_evals=$(awk -F, '$3 == "acceleration_eval_0" {print $4}' "$work/pysph/profile_info.csv")
  s_particles=$(awk '/particles/ {print $2; exit}' "$work/sluice_before.txt")
  s_fluid=$(awk '/particles/ {gsub(/\(/, "", $3); print $3; exit}' "$work/sluice_before.txt")
  s_steps=$(awk '/steps/ {print $2; exit}' "$work/sluice_before.txt")
  s_per_step=$(awk '/steps/ {gsub(/\(/, "", $3); print $3; exit}' "$work/sluice_before.txt")
  s_wall=$(awk '/loop time/ {print $3; exit}' "$work/sluice_before.txt")
  s_wall2=$(awk '/loop time/ {print $3; exit}' "$work/sluice_after.txt")
  /usr/bin/python3 - "$digits" "$p_particles" "$p_evals" "$p_wall" "$s_particles" "$s_steps" "$s_per_step" \
    "$s_wall" "$s_wall2" "$p_fluid" "$s_fluid" "$@" <<'PY'
import sys
digits, pp, pe, pw, sp, ss, sk, sw, sw2, pf, sf = sys.argv[1:12]
digits, pp, pe, pw, sp, ss, sk, sw, sw2 = int(digits), int(pp), int(pe), float(pw), int(sp), int(ss), int(sk), float(sw), float(sw2)
pf, sf = int(pf), int(sf)
p_rate = pp * pe / pw
s_rate, s_rate2 = sp * ss * sk / sw, sp * ss * sk / sw2
for title in sys.argv[12:]:
    print(title)
print(f"{'':15} {'particles':>10} {'evaluations':>12} {'wall [s]':>9} {'M particle-evals/s':>19}")
print(f"{'sluice, before':15} {sp:>10} {ss*sk:>12} {sw:>9.2f} {s_rate*1e-6:>19.{digits}f}")
print(f"{'PySPH':15} {pp:>10} {pe:>12} {pw:>9.2f} {p_rate*1e-6:>19.{digits}f}")
print(f"{'sluice, after':15} {sp:>10} {ss*sk:>12} {sw2:>9.2f} {s_rate2*1e-6:>19.{digits}f}")
print(f"ratio (sluice / PySPH, per force evaluation): {s_rate/p_rate:.1f}x and {s_rate2/p_rate:.1f}x "
      f"(sluice before and after PySPH; the machine's drift between them: {s_rate2/s_rate:.2f})")
pf_rate, sf_rate, sf_rate2 = pf * pe / pw, sf * ss * sk / sw, sf * ss * sk / sw2
print(f"per fluid particle and evaluation (fluid: sluice {sf}, PySPH {pf}): {sf_rate/pf_rate:.1f}x and {sf_rate2/pf_rate:.1f}x")
# The same simulated time: wall seconds per fluid particle (sluice's summary counts the loop, PySPH's
# its run; both without set-up).
print(f"per fluid particle over the same simulated time ({sk*ss} sluice evaluations, {pe} PySPH's): "
      f"{(pw/pf)/(sw/sf):.1f}x and {(pw/pf)/(sw2/sf):.1f}x")
PY
}
