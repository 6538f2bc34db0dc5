#!/usr/bin/env bash
# Side-by-side speed in 3D: PySPH's SPHERIC test 2 example (dam_break_3d.py) and sluice's spheric2 at
# the same particle spacing, both on one thread, run one after the other in one go. Not part of CI.
#
#   bash bench/peer_pysph_3d.sh [DX] [END_TIME] [sluice run options...]
#       (default dx = 0.04 m, 0.05 s of simulated time; e.g. --set physics.wall_boundary=dynamic, the
#       wall treatment closest to PySPH's, whose wall particles integrate the continuity equation too)
#
# Needs Debian's python3-pysph (apt-get install python3-pysph) and a release build (make build).
# Speed is particles x force evaluations / wall seconds, also per fluid particle and over the same
# simulated time (bench/peer_report.sh): PySPH's EPEC integrator evaluates twice per step, spheric2's
# leapfrog once, at a longer step, and the two fill their walls differently (sluice layers to 2h).
set -euo pipefail
cd "$(dirname "$0")/.."
source bench/peer_report.sh
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
run_sluice after

s_target=$(awk '/pair loop/ {print $3; exit}' "$work/sluice_before.txt")
peer_report "$work" 3 "3D dam break (SPHERIC test 2), dx = $dx m, end time $end s, one thread; sluice's pair loop: $s_target" \
  "sluice: the spheric2 case${extra[*]:+ with ${extra[*]}}"
