#!/usr/bin/env bash
# Two builds of sluice side by side: the same case run by each in turn, ROUNDS times, on one thread;
# the medians of their stepping loops' times (the summaries' "loop time"), their ratio, and whether
# their last frames are bit for bit the same. For a change that must not slow the program (or to
# show one that speeds it up); build the other side from another commit, e.g. with
#   git worktree add /tmp/before HEAD~1 && cmake -S /tmp/before -B /tmp/before/build && cmake --build /tmp/before/build --target sluice
#
#   bash bench/compare_builds.sh BEFORE_SLUICE AFTER_SLUICE [ROUNDS] [sluice run options...]
#       (default: 5 rounds of the default dam break at dx = 0.05 m to t = 0.5 s, 23,236 particles)
set -euo pipefail
before=$1 after=$2
rounds=${3:-5}
shift 3 || shift $#
options=("$@")
[ ${#options[@]} -gt 0 ] || options=(dam_break --set domain.dx=0.05 --set time.end=0.5 --set output.interval=0.1)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
loop() { sed -n 's/^  loop time *\([0-9.]*\) s.*/\1/p' "$1"; }
for k in $(seq "$rounds"); do
  for side in before after; do
    "${!side}" run "${options[@]}" -q --threads 1 -o "$work/$side" > "$work/$side.txt"
    echo "$(loop "$work/$side.txt")" >> "$work/$side.times"
  done
  echo "round $k: before $(tail -1 "$work/before.times") s, after $(tail -1 "$work/after.times") s"
done
/usr/bin/python3 - "$work" <<'PY'
import glob, statistics, sys
import numpy as np
work = sys.argv[1]
b, a = ([float(x) for x in open(f"{work}/{s}.times")] for s in ("before", "after"))
last = lambda s: sorted(glob.glob(f"{work}/{s}/frames/*.npz"))[-1]
fb, fa = np.load(last("before")), np.load(last("after"))
same = fb.files == fa.files and all(np.array_equal(fb[k], fa[k]) for k in fb.files)
print(f"after / before = {statistics.median(a) / statistics.median(b):.3f} (medians {statistics.median(a):.3f} s and "
      f"{statistics.median(b):.3f} s of {len(a)} rounds); last frames {'bit for bit the same' if same else 'DIFFER'}")
PY
