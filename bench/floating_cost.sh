#!/usr/bin/env bash
# What a floating body costs: a case with its floating walls against the same case with them held
# where they start (their [wall.floating] tables removed), run side by side, alternating, one thread
# each (not part of CI). The floating body moves and the held one does not, so their step counts
# differ: the measure is particle-evaluations per second. Prints each run's, and the floating runs'
# cost per evaluation as a multiple of the held runs'.
#
#   bash bench/floating_cost.sh [CASE] [ROUNDS] [sluice run options...]
#       (default: floating_box to t = 0.5 s, 3 rounds)
#
# Needs a release build (make build).
set -euo pipefail
cd "$(dirname "$0")/.."
case_arg=${1:-floating_box}
rounds=${2:-3}
shift 2 || shift $# || true
extra=("$@")
[ ${#extra[@]} -gt 0 ] || extra=(--set time.end=0.5)
sluice=${SLUICE:-build/release/sluice}
[ -x "$sluice" ] || { echo "floating_cost: $sluice not built; run make build" >&2; exit 1; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
grep -o 'avx512[a-z]*' /proc/cpuinfo | sort -u | tr '\n' ' ' | sed 's/^/cpu: /; s/$/\n/' || true
echo "cpu: $(lscpu | sed -n 's/^Model name: *//p'), $(nproc) cores"
"$sluice" init --from "$case_arg" "$work/floating.toml" >/dev/null
# The same case without its [wall.floating] tables (each runs to the next table header or the end).
awk '/^\[wall\.floating\]/ {skip = 1; next} /^\[/ {skip = 0} !skip' "$work/floating.toml" >"$work/held.toml"
grep -q '^\[wall\.floating\]' "$work/floating.toml" || { echo "floating_cost: $case_arg has no floating wall" >&2; exit 1; }
run() {  # label, case file
  local out
  out=$("$sluice" run "$2" -q --threads 1 -o "$work/$1" "${extra[@]}")
  rm -rf "${work:?}/$1"
  echo "$out" | awk '/loop time/ {t = $3} /^ *steps/ {s = $2} /speed/ {for (i = 2; i <= NF; ++i) if ($i ~ /particle-evaluations/) e = $(i - 2)}
                     END {print t, s, e}'
}
floating_sum=0 held_sum=0
for ((r = 1; r <= rounds; ++r)); do
  read -r tf sf ef < <(run floating "$work/floating.toml")
  read -r th sh eh < <(run held "$work/held.toml")
  printf 'round %d: floating %7.2f s, %6d steps (%s M particle-evaluations/s); held %7.2f s, %6d steps (%s)\n' \
    "$r" "$tf" "$sf" "$ef" "$th" "$sh" "$eh"
  floating_sum=$(awk -v a="$floating_sum" -v b="$ef" 'BEGIN {print a + b}')
  held_sum=$(awk -v a="$held_sum" -v b="$eh" 'BEGIN {print a + b}')
done
awk -v f="$floating_sum" -v h="$held_sum" \
  'BEGIN {printf "floating: %.3f times the held runs'"'"' time per particle-evaluation\n", h / f}'
