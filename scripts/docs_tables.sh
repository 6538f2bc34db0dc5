#!/usr/bin/env bash
# Regenerates the measured tables the documentation includes (docs/generated/*.md) by running the
# commands that measure them, on this machine. Not part of CI: the full validation takes about
# 2.5 minutes on one core, the PySPH comparison about 3 minutes.
#
#   bash scripts/docs_tables.sh [validation] [speed]     # default: both
#   THREADS=2 bash scripts/docs_tables.sh validation     # threads per validation run (default 1)
#
# Then `make docs` builds the site with them. speed needs Debian's python3-pysph.
set -euo pipefail
cd "$(dirname "$0")/.."
sluice=${SLUICE:-build/release/sluice}
[ -x "$sluice" ] || { echo "docs_tables: $sluice not built; run make build" >&2; exit 1; }
work=build/docs-tables
mkdir -p "$work" docs/generated
what=("$@")
[ ${#what[@]} -eq 0 ] && what=(validation speed)

for w in "${what[@]}"; do
  case $w in
    validation)
      command="sluice validate --threads ${THREADS:-1}"
      rm -rf "$work/validation"
      start=$(date +%s%N)
      status=0
      "$sluice" validate --threads "${THREADS:-1}" -q -o "$work/validation" > "$work/validation.txt" || status=$?
      [ $status -le 1 ] || { cat "$work/validation.txt" >&2; exit $status; }  # 1: a check failed, still a table
      seconds=$(( ($(date +%s%N) - start) / 1000000000 ))
      /usr/bin/python3 docs/gen_tables.py validation "$work/validation" "$command" "$seconds" "$sluice" \
        > docs/generated/validation_2d.md
      echo "docs_tables: wrote docs/generated/validation_2d.md ($command, $seconds s)"
      ;;
    speed)
      bash bench/peer_pysph.sh 0.3 > "$work/peer_2d.txt"
      /usr/bin/python3 docs/gen_tables.py text "$work/peer_2d.txt" "bash bench/peer_pysph.sh 0.3" \
        > docs/generated/speed_peer_2d.md
      bash bench/peer_pysph.sh 0.3 --simd AVX2 > "$work/peer_2d_avx2.txt"
      /usr/bin/python3 docs/gen_tables.py text "$work/peer_2d_avx2.txt" "bash bench/peer_pysph.sh 0.3 --simd AVX2" \
        > docs/generated/speed_peer_2d_avx2.md
      echo "docs_tables: wrote docs/generated/speed_peer_2d.md and speed_peer_2d_avx2.md"
      ;;
    *) echo "docs_tables: unknown table '$w'; expected validation or speed" >&2; exit 2 ;;
  esac
done
