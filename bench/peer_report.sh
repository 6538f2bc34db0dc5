# Sourced by bench/peer_pysph.sh and bench/peer_pysph_3d.sh: the table of one side-by-side run.
#
#   peer_report WORK DIGITS TITLE...
#
# WORK holds PySPH's log (pysph.txt) and profile (pysph/profile_info.csv) and sluice's two summaries
# (sluice_before.txt, sluice_after.txt); DIGITS is how many decimals the rates get; each TITLE is a
# line printed above the table.
peer_report() {
  local work=$1 digits=$2
  shift 2
  local p_particles p_wall p_evals s_particles s_steps s_per_step s_wall s_wall2
  p_particles=$(awk '/Total:/ {print $2}' "$work/pysph.txt")
  p_wall=$(awk '/Run took:/ {print $3}' "$work/pysph.txt")
  p_evals=$(awk -F, '$3 == "acceleration_eval_0" {print $4}' "$work/pysph/profile_info.csv")
  s_particles=$(awk '/particles/ {print $2; exit}' "$work/sluice_before.txt")
  s_steps=$(awk '/steps/ {print $2; exit}' "$work/sluice_before.txt")
  s_per_step=$(awk '/steps/ {gsub(/\(/, "", $3); print $3; exit}' "$work/sluice_before.txt")
  s_wall=$(awk '/loop time/ {print $3; exit}' "$work/sluice_before.txt")
  s_wall2=$(awk '/loop time/ {print $3; exit}' "$work/sluice_after.txt")
  /usr/bin/python3 - "$digits" "$p_particles" "$p_evals" "$p_wall" "$s_particles" "$s_steps" "$s_per_step" \
    "$s_wall" "$s_wall2" "$@" <<'PY'
import sys
digits, pp, pe, pw, sp, ss, sk, sw, sw2 = sys.argv[1:10]
digits, pp, pe, pw, sp, ss, sk, sw, sw2 = int(digits), int(pp), int(pe), float(pw), int(sp), int(ss), int(sk), float(sw), float(sw2)
p_rate = pp * pe / pw
s_rate, s_rate2 = sp * ss * sk / sw, sp * ss * sk / sw2
for title in sys.argv[10:]:
    print(title)
print(f"{'':15} {'particles':>10} {'evaluations':>12} {'wall [s]':>9} {'M particle-evals/s':>19}")
print(f"{'sluice, before':15} {sp:>10} {ss*sk:>12} {sw:>9.2f} {s_rate*1e-6:>19.{digits}f}")
print(f"{'PySPH':15} {pp:>10} {pe:>12} {pw:>9.2f} {p_rate*1e-6:>19.{digits}f}")
print(f"{'sluice, after':15} {sp:>10} {ss*sk:>12} {sw2:>9.2f} {s_rate2*1e-6:>19.{digits}f}")
print(f"ratio (sluice / PySPH, per force evaluation): {s_rate/p_rate:.1f}x and {s_rate2/p_rate:.1f}x "
      f"(sluice before and after PySPH; the machine's drift between them: {s_rate2/s_rate:.2f})")
PY
}
