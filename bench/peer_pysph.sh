#!/usr/bin/env bash
# Side-by-side speed of PySPH's 2D dam break and sluice's mirror of it (bench/peer_pysph_dam_break.toml),
# both on one thread, run one after the other in one go. Not part of CI.
#
#   bash bench/peer_pysph.sh [END_TIME] [sluice run options...]
#       (default 0.5 s of simulated time; PySPH's own is 2.5 s; e.g. --set domain.pair_precision=single)
#
# Needs Debian's python3-pysph (apt-get install python3-pysph) and a release build (make build).
# Speed is particles x force evaluations / wall seconds, also per fluid particle and over the same
# simulated time (bench/peer_report.sh); PySPH's PECIntegrator and the mirror's leapfrog both evaluate
# once per step, at CFL 0.3.
set -euo pipefail
cd "$(dirname "$0")/.."
source bench/peer_report.sh
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
run_sluice after

peer_report "$work" 2 "2D dam break (PySPH dam_break_2d.py geometry), end time $end s, one thread"
