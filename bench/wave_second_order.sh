#!/usr/bin/env bash
# Does second-order generation remove the free second harmonic? (docs/waves.md, "Second-order
# generation"). The wave of wave_flume (H = 0.08 m, T = 1.2 s, h = 0.4 m, kh = 1.30) from a piston
# driven by first-order theory and by Madsen's second-order motion, in a 7 m flume with a damping zone
# from 5.1 m, to 12 s, with gauges every 0.15 m: a first-order piston also makes a free second
# harmonic, which beats against Stokes' bound one over 2 pi / (k(2 omega) - 2 k) = 1.34 m, so that a2
# swings along the flume; with order = 2 it should stay at the bound harmonic (0.0046 m). Prints a2
# and a1 at each gauge for both runs, their spread, and the wall time. Two runs, one thread each, side
# by side (not part of CI; at dx = 0.01 m, H/dx = 8, each took 28 minutes on a 2-core AMD EPYC).
#
#   bash bench/wave_second_order.sh [DX] [OUT]       (default 0.01; OUT keeps the runs)
#
# Needs a release build (make build).
set -euo pipefail
cd "$(dirname "$0")/.."
dx=${1:-0.01}
sluice=$(realpath "${SLUICE:-build/release/sluice}")
[ -x "$sluice" ] || { echo "wave_second_order: $sluice not built; run make build" >&2; exit 1; }
if [ -n "${2:-}" ]; then work=$(realpath -m "$2"); mkdir -p "$work"; else work=$(mktemp -d); trap 'rm -rf "$work"' EXIT; fi
grep -o 'avx512[a-z]*' /proc/cpuinfo | sort -u | tr '\n' ' ' | sed 's/^/cpu: /; s/$/\n/' || true
echo "cpu: $(lscpu | sed -n 's/^Model name: *//p'), $(nproc) cores"

for order in 1 2; do
  cat > "$work/flume$order.toml" <<EOF2
[case]
name = "wave_order$order"
[domain]
dx = $dx
kernel = "wendland_c2"
[tank]
width = 7.0
height = 0.7
[fluid]
sound_speed = 22.0
[physics]
artificial_viscosity = 0.0
shifting = 0.0
[time]
end = 12.0
[output]
interval = 4.0
[[water]]
min = [0.12, 0.0]
max = [7.0, 0.4]
[damping]
start = [5.1, 0.0]
length = 1.9
[[wall]]
name = "piston"
min = [0.04, 0.0]
max = [0.12, 0.65]
[wall.translation]
law = "wave"
direction = [1.0, 0.0]
height = 0.08
period = 1.2
depth = 0.4
order = $order
ramp = 2
EOF2
  for n in $(seq 2 32); do
    x=$(awk -v n="$n" 'BEGIN { printf "%.3f", 0.12 + 0.15 * n }')
    printf '[[probe]]\nname = "x%s"\ntype = "gauge"\npoint = [%s, 0.0]\nmeasure = "surface"\ninterval = 0.02\n' \
      "$(awk -v n="$n" 'BEGIN { printf "%.2f", 0.15 * n }')" "$x" >> "$work/flume$order.toml"
  done
done

one() {
  "$sluice" run "$work/flume$1.toml" -o "$work/order$1" -q --threads 1 > "$work/order$1.log" 2>&1
  "$sluice" analyze "$work/order$1" > "$work/order$1.analysis" 2>&1
}
one 1 &
one 2 &
wait

# gauges.csv: gauge, ..., distance (3), ..., first_harmonic_amplitude (10), second_harmonic_amplitude (12)
printf '%-10s %12s %12s %12s %12s\n' "from paddle" "a1 order 1" "a1 order 2" "a2 order 1" "a2 order 2"
paste -d, "$work/order1/analysis/gauges.csv" "$work/order2/analysis/gauges.csv" |
  awk -F, 'NR > 1 && $10 != "" { n = NF / 2; printf "%-10.2f %12.5f %12.5f %12.5f %12.5f\n", $3, $10, $(n + 10), $12, $(n + 12) }'
for order in 1 2; do
  awk -F, -v o="$order" 'NR > 1 && $12 != "" { a = $12; if (n == 0 || a < lo) lo = a; if (n == 0 || a > hi) hi = a; s += a; n++ }
    END { printf "order %s: a2 from %.5f to %.5f m over %d gauges (mean %.5f; Stokes bound 0.0046)\n", o, lo, hi, n, s / n }' \
    "$work/order$order/analysis/gauges.csv"
  echo "order $order: $(grep -E 'wall time|steps' "$work/order$order.log" | tr '\n' ' ')"
done
