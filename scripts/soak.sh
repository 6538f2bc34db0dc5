#!/usr/bin/env bash
# Soak runs (not in CI): the default case at dx = 0.1 m to 30 s and the beach case to its end, each
# checked against the solver's invariants over the whole run from its diagnostics.csv (every frame):
# densities in (0, 1.5 rho0], max speed below c0, zero leaks. The instability guard also stops a run
# with a non-zero exit if any particle goes non-finite or leaves the tank.
#
#   bash scripts/soak.sh [OUTPUT_ROOT]      (default out/soak; needs `make build`)
set -euo pipefail
cd "$(dirname "$0")/.."
root=${1:-out/soak}
sluice=build/release/sluice
[ -x "$sluice" ] || { echo "soak: $sluice not built; run make build" >&2; exit 1; }

check() {  # name, output dir, rho0, c0
  local name=$1 dir=$2 rho0=$3 c0=$4
  awk -F, -v rho0="$rho0" -v c0="$c0" -v name="$name" '
    NR == 1 { for (k = 1; k <= NF; ++k) col[$k] = k; next }
    { if ($col["min_density"] < min_rho || NR == 2) min_rho = $col["min_density"];
      if ($col["max_density"] > max_rho) max_rho = $col["max_density"];
      if ($col["max_speed"] > max_v) max_v = $col["max_speed"];
      leaks = $col["leaks"]; wall = $col["wall_time"]; t = $col["time"] }
    END {
      ok = (min_rho > 0 && max_rho <= 1.5 * rho0 && max_v < c0 && leaks == 0)
      printf "%-10s t = %s s  wall %s s  density %.2f..%.2f kg/m^3  max speed %.3f m/s  leaks %d  %s\n",
             name, t, wall, min_rho, max_rho, max_v, leaks, ok ? "OK" : "FAILED"
      exit ok ? 0 : 1
    }' "$dir/diagnostics.csv"
}

status=0
"$sluice" run dam_break --set domain.dx=0.1 -q -o "$root/dam_break_dx0.1" > "$root.dam_break.txt" || status=1
check dam_break "$root/dam_break_dx0.1" 1000 20 || status=1
"$sluice" run beach -q -o "$root/beach" > "$root.beach.txt" || status=1
check beach "$root/beach" 1000 20 || status=1
exit $status
