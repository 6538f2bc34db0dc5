#!/usr/bin/env bash
# Several processes against one, side by side in one go (not part of CI): a case on 1 process with 1
# thread, on 1 process with 2 threads (OpenMP alone), and under mpirun on 2, 4 and 8 processes with 1
# thread each (4 and 8 oversubscribe a 2-core machine: their times say nothing of speed there, their
# exchange volumes do). Prints, per run, the stepping loop's time, the speed-up over one process and
# thread, and what the processes exchange per step.
#
#   bash bench/mpi_scaling.sh [CASE] [sluice run options...]
#       (default: the dam break at domain.dx = 0.025 m, 86k particles, to t = 0.1 s)
#
# Needs a release build (make build) and Open MPI's mpirun (scripts/setup.sh installs it).
set -euo pipefail
cd "$(dirname "$0")/.."
case_arg=${1:-dam_break}
shift || true
extra=("$@")
[ ${#extra[@]} -gt 0 ] || extra=(--set domain.dx=0.025 --set time.end=0.1)
sluice=${SLUICE:-build/release/sluice}
[ -x "$sluice" ] || { echo "mpi_scaling: $sluice not built; run make build" >&2; exit 1; }
command -v mpirun >/dev/null || { echo "mpi_scaling: mpirun not found; run scripts/setup.sh" >&2; exit 1; }
# Open MPI refuses to run as root unless told (containers, CI).
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMP_WAIT_POLICY=PASSIVE
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
grep -o 'avx512[a-z]*' /proc/cpuinfo | sort -u | tr '\n' ' ' | sed 's/^/cpu: /; s/$/\n/' || true
echo "cpu: $(lscpu | sed -n 's/^Model name: *//p'), $(nproc) cores"

run() {  # label, processes, threads
  local label=$1 np=$2 threads=$3 out="$work/$1.txt"
  if [ "$np" -eq 1 ]; then
    "$sluice" run "$case_arg" -q --threads "$threads" -o "$work/$label" "${extra[@]}" > "$out"
  else
    mpirun --oversubscribe -np "$np" "$sluice" run "$case_arg" -q --threads "$threads" -o "$work/$label" \
      "${extra[@]}" > "$out"
  fi
  awk -v label="$label" '
    /particles / && !p {p = $2}
    /steps / && !s {s = $2}
    /loop time/ {t = $3}
    /exchanges/ {mb = $2; ms = $8; gh = $(NF-4)}
    END {printf "%s %s %s %s %s %s %s\n", label, p, s, t, (mb == "" ? "-" : mb), (ms == "" ? "-" : ms), (gh == "" ? "-" : gh)}' "$out"
}

{
  run 1x1 1 1
  run 1x2 1 2
  run 2x1 2 1
  run 4x1 4 1
  run 8x1 8 1
} > "$work/table.txt"

/usr/bin/python3 - "$work/table.txt" <<'PY'
import sys
rows = [line.split() for line in open(sys.argv[1])]
base = float(rows[0][3])
print(f"{'processes x threads':>20} {'particles':>10} {'steps':>6} {'loop s':>8} {'speed-up':>9} "
      f"{'MB/step':>8} {'ms/step':>8} {'ghosts %':>9}")
for label, particles, steps, loop, mb, ms, ghosts in rows:
    print(f"{label:>20} {particles:>10} {steps:>6} {float(loop):8.2f} {base / float(loop):8.2f}x "
          f"{mb:>8} {ms:>8} {ghosts:>9}")
PY
