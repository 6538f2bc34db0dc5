#!/usr/bin/env bash
# What a moving wall costs: a case with its walls moving against the same case with them held where
# they start (wall[k].translation.law and .rotation.law = "none"), run side by side, alternating, one
# thread each (not part of CI). Prints each run's stepping-loop time and particle-evaluations per
# second, and the moving runs' speed as a share of the fixed runs'.
#
#   bash bench/moving_wall_cost.sh [CASE] [ROUNDS] [sluice run options...]
#       (default: piston_still_water to t = 1 s, 3 rounds)
#
# Needs a release build (make build).
set -euo pipefail
cd "$(dirname "$0")/.."
case_arg=${1:-piston_still_water}
rounds=${2:-3}
shift 2 || shift $# || true
extra=("$@")
[ ${#extra[@]} -gt 0 ] || extra=(--set time.end=1.0)
sluice=${SLUICE:-build/release/sluice}
[ -x "$sluice" ] || { echo "moving_wall_cost: $sluice not built; run make build" >&2; exit 1; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
grep -o 'avx512[a-z]*' /proc/cpuinfo | sort -u | tr '\n' ' ' | sed 's/^/cpu: /; s/$/\n/' || true
echo "cpu: $(lscpu | sed -n 's/^Model name: *//p'), $(nproc) cores"
# Every moving wall of the case held: its laws set to none.
fixed=()
"$sluice" init --from "$case_arg" "$work/case.toml" >/dev/null
walls=$(grep -c '^\[\[wall\]\]' "$work/case.toml" || true)
for ((k = 0; k < ${walls:-0}; ++k)); do
  fixed+=(--set "wall[$k].translation.law=none" --set "wall[$k].rotation.law=none")
done
run() {  # label, options...
  local label=$1 out
  shift
  out=$("$sluice" run "$case_arg" -q --threads 1 -o "$work/$label" "${extra[@]}" "$@")
  rm -rf "${work:?}/$label"
  echo "$out" | awk '/loop time/ {t = $3} /speed/ {for (i = 2; i <= NF; ++i) if ($i ~ /particle-evaluations/) e = $(i - 2)}
                     END {print t, e}'
}
moving_sum=0 fixed_sum=0
for ((r = 1; r <= rounds; ++r)); do
  read -r tm em < <(run moving)
  read -r tf ef < <(run fixed "${fixed[@]}")
  printf 'round %d: moving %7.2f s (%s M particle-evaluations/s), fixed %7.2f s (%s)\n' "$r" "$tm" "$em" "$tf" "$ef"
  moving_sum=$(awk -v a="$moving_sum" -v b="$tm" 'BEGIN {print a + b}')
  fixed_sum=$(awk -v a="$fixed_sum" -v b="$tf" 'BEGIN {print a + b}')
done
awk -v m="$moving_sum" -v f="$fixed_sum" -v w="$walls" \
  'BEGIN {printf "moving: %.3f times the loop time with the %d walls held\n", m / f, w}'
