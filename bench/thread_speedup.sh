#!/usr/bin/env bash
# Two threads over one, side by side in one go, at about 3k, 20k, 100k and 1M particles: in 2D the
# default dam break (dx = 0.13, 0.05, 0.022, 0.007 m: 4,246 / 23,236 / 109,435 / 1,026,466
# particles), in 3D SPHERIC test 2 (dx = 0.09, 0.035, 0.025, 0.0105 m: about 5k / 48k / 100k / 906k).
# Each size is measured ROUNDS times on one thread and on two, alternated, by sluice-bench-run (the
# solver's steps alone, in a child process each); then the pair loop's share of a one-thread run of
# the dam break at 23k particles, from perf's samples when perf is installed.
#
#   bash bench/thread_speedup.sh [ROUNDS]        (after make build; default 2 rounds)
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
bin=${SLUICE_BUILD:-$here/../build/release}
rounds=${1:-2}
threads=$(for _ in $(seq "$rounds"); do printf '1,2,'; done)
threads=${threads%,}
out=$(mktemp -d /tmp/sluice_thread_speedup.XXXXXX)
trap 'rm -rf "$out"' EXIT

echo "CPU: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ *//'), vector extensions:" \
     "$(grep -o 'avx512[a-z]*\|avx2' /proc/cpuinfo | sort -u | tr '\n' ' ')"
for spec in "dam_break 0.13,0.05,0.022,0.007" "spheric2 0.09,0.035,0.025,0.0105"; do
  set -- $spec
  echo "== $1 (dx $2)"
  "$bin/sluice-bench-run" --case "$1" --dx "$2" --threads "$threads" --steps 20 --csv "$out/$1.csv" |
    grep -E "threads over one|^ *[0-9.]+ +[12] " || true
done

if command -v perf >/dev/null && perf stat -e task-clock true >/dev/null 2>&1; then
  echo "== the pair loop's share of a one-thread run (dam break, dx = 0.05 m, to t = 0.5 s)"
  perf record -q -o "$out/perf.data" "$bin/sluice" run dam_break -q --threads 1 --fixed-threads -o "$out/run" \
    --set domain.dx=0.05 --set time.end=0.5 >/dev/null 2>&1
  perf report -i "$out/perf.data" --no-children --sort sym 2>/dev/null | awk '
    /%/ { share = $1; sub("%", "", share); total += share
          if ($0 ~ /rate_loop/) pair += share; else if ($0 ~ /shepard_loop/) shepard += share }
    END { printf "pair loop %.1f %%, Shepard filter %.1f %%, everything else %.1f %% of the samples\n",
                 pair, shepard, total - pair - shepard }'
else
  echo "(perf is not available here: no share of the pair loop)"
fi
