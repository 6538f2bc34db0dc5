#!/usr/bin/env bash
# What a floating body costs: a case with its floating walls locked in every degree of freedom (all
# the floating code runs: its loads, its contacts, its reach, its dynamics, and it stays where it
# starts) against the same case with them held where they start (their [wall.floating] tables
# removed), run side by side, alternating, one thread each (not part of CI); and the case as it is,
# its bodies free, whose moving bodies stir the water into more work per step. The measure is
# particle-evaluations per second. Prints each run's, and the locked and free runs' time per
# evaluation as a multiple of the held runs'.
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
# The same case without its [wall.floating] tables (each runs to the next table header or the end),
# and with every degree of freedom of each locked.
awk '/^\[wall\.floating\]/ {skip = 1; next} /^\[/ {skip = 0} !skip' "$work/floating.toml" >"$work/held.toml"
if grep -q '^dimension = 3' "$work/floating.toml"; then all='["x", "y", "z", "rx", "ry", "rz"]'; else all='["x", "y", "rz"]'; fi
awk -v all="$all" '/^\[wall\.floating\]/ {print; print "lock = " all; skip = 1; next} /^\[/ {skip = 0}
                   skip && /^lock = / {next} {print}' "$work/floating.toml" >"$work/locked.toml"
grep -q '^\[wall\.floating\]' "$work/floating.toml" || { echo "floating_cost: $case_arg has no floating wall" >&2; exit 1; }
run() {  # label, case file
  local out
  out=$("$sluice" run "$2" -q --threads 1 -o "$work/$1" "${extra[@]}")
  rm -rf "${work:?}/$1"
  echo "$out" | awk '/loop time/ {t = $3} /^ *steps/ {s = $2} /speed/ {for (i = 2; i <= NF; ++i) if ($i ~ /particle-evaluations/) e = $(i - 2)}
                     END {print t, s, e}'
}
free_sum=0 locked_sum=0 held_sum=0
for ((r = 1; r <= rounds; ++r)); do
  read -r tl sl el < <(run locked "$work/locked.toml")
  read -r th sh eh < <(run held "$work/held.toml")
  read -r tf sf ef < <(run free "$work/floating.toml")
  printf 'round %d: locked %7.2f s, %6d steps (%s M particle-evaluations/s); held %7.2f s, %6d steps (%s); free %7.2f s, %6d steps (%s)\n' \
    "$r" "$tl" "$sl" "$el" "$th" "$sh" "$eh" "$tf" "$sf" "$ef"
  locked_sum=$(awk -v a="$locked_sum" -v b="$el" 'BEGIN {print a + b}')
  held_sum=$(awk -v a="$held_sum" -v b="$eh" 'BEGIN {print a + b}')
  free_sum=$(awk -v a="$free_sum" -v b="$ef" 'BEGIN {print a + b}')
done
awk -v l="$locked_sum" -v h="$held_sum" -v f="$free_sum" \
  'BEGIN {printf "locked: %.3f times the held runs'"'"' time per particle-evaluation; free: %.3f\n", h / l, h / f}'
