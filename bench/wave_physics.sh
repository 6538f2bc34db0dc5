#!/usr/bin/env bash
# What each physics option does to a wave (docs/waves.md, "Accuracy, kernel and viscosity"): the wave
# of wave_flume (H = 0.08 m, T = 1.2 s, h = 0.4 m) in a 7 m flume with a damping zone from 5.1 m, to
# 12 s, gauges every half wavelength; one run per row, one thread each, two side by side (not part of
# CI; about 25 minutes on 2 cores at dx = 0.02 m). Prints each run's first-harmonic height against the
# target at each gauge, the decay per wavelength and the wall time.
#
#   bash bench/wave_physics.sh [DX]          (default 0.02)
#
# Needs a release build (make build).
set -euo pipefail
cd "$(dirname "$0")/.."
dx=${1:-0.02}
sluice=$(realpath "${SLUICE:-build/release/sluice}")
[ -x "$sluice" ] || { echo "wave_physics: $sluice not built; run make build" >&2; exit 1; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
grep -o 'avx512[a-z]*' /proc/cpuinfo | sort -u | tr '\n' ' ' | sed 's/^/cpu: /; s/$/\n/' || true
echo "cpu: $(lscpu | sed -n 's/^Model name: *//p'), $(nproc) cores"

cat > "$work/flume.toml" <<EOF
[case]
name = "wave_physics"
[domain]
dx = $dx
kernel = "wendland_c2"
[tank]
width = 7.0
height = 0.7
[fluid]
sound_speed = 22.0
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
order = 2
ramp = 2
EOF
for n in 1 2 3 4 5; do
  x=$(awk -v n="$n" 'BEGIN { printf "%.3f", 0.12 + n * 1.9361 / 2 }')
  printf '[[probe]]\nname = "g%s"\ntype = "gauge"\npoint = [%s, 0.0]\nmeasure = "surface"\ninterval = 0.02\n' \
    "$(awk -v n="$n" 'BEGIN { print n / 2 }')" "$x" >> "$work/flume.toml"
done

labels=(a0.02_shift a0.01_shift a0_shift a0.02 a0.01 a0 a0.02_shift_noshepard a0.02_shift_renormalised a0.02_shift_h1.5)
sets=("physics.artificial_viscosity=0.02"
      "physics.artificial_viscosity=0.01"
      "physics.artificial_viscosity=0"
      "physics.artificial_viscosity=0.02 physics.shifting=0"
      "physics.artificial_viscosity=0.01 physics.shifting=0"
      "physics.artificial_viscosity=0 physics.shifting=0"
      "physics.artificial_viscosity=0.02 physics.shepard_every=0"
      "physics.artificial_viscosity=0.02 physics.density_diffusion_gradient=renormalised"
      "physics.artificial_viscosity=0.02 domain.h_over_dx=1.5")

one() {
  local k=$1 args=()
  for s in ${sets[$k]}; do args+=(--set "$s"); done
  "$sluice" run "$work/flume.toml" -o "$work/${labels[$k]}" -q --threads 1 "${args[@]}" > "$work/${labels[$k]}.log" 2>&1
  "$sluice" analyze "$work/${labels[$k]}" > "$work/${labels[$k]}.analysis" 2>&1
}
for ((k = 0; k < ${#labels[@]}; k += 2)); do
  one "$k" &
  if ((k + 1 < ${#labels[@]})); then one $((k + 1)) & fi
  wait
done

printf '%-28s %8s %8s %8s %8s %8s %10s %10s\n' "physics (dx = $dx m)" 0.5L 1L 1.5L 2L 2.5L "decay/L" "wall (s)"
for ((k = 0; k < ${#labels[@]}; ++k)); do
  a="$work/${labels[$k]}.analysis"
  errors=$(awk '$1 ~ /^g[0-9.]+$/ { printf "%8s ", $8 }' "$a")
  decay=$(awk '$1 == "decay" { print $2 "%" }' "$a")
  wall=$(awk '$1 == "wall" && $2 == "time" { print $3 }' "$work/${labels[$k]}.log")
  printf '%-28s %s %10s %10s\n' "${labels[$k]}" "$errors" "$decay" "$wall"
done
