#!/usr/bin/env bash
# `make fuzz`: builds the libFuzzer targets (preset fuzz: clang, ASan + UBSan), makes seed corpora
# from the built-in cases and a tiny real run, and runs each target in turn (one process at a time)
# for FUZZ_SECONDS (default 60) each. Exits non-zero if any target found a crash, hang, leak or
# sanitizer report; the input that did it is left in build/fuzz/artifacts/<target>/ (keep it as a
# regression test in tests/fuzz_regressions/<target>/ once fixed).
#
#   FUZZ_SECONDS=600 make fuzz            # longer
#   FUZZ_TARGETS="frame" make fuzz        # some targets only (case, checkpoint, frame, mesh)
#   SLUICE_BIN=path/to/sluice             # the binary that makes the seed run (default: the release build)
#   FUZZ_PRESET=fuzz-ub                   # UBSan only, no ASan: several times faster on meshes, for
#                                         # long runs; replay its corpus under the fuzz preset after:
#                                         # FUZZ_SECONDS=0 make fuzz runs each target once over its corpus
set -euo pipefail
cd "$(dirname "$0")/.."

seconds=${FUZZ_SECONDS:-60}
targets=${FUZZ_TARGETS:-case checkpoint frame mesh}
sluice=${SLUICE_BIN:-build/release/sluice}
preset=${FUZZ_PRESET:-fuzz}
dir=build/fuzz
bin=build/$preset/fuzz

mkdir -p "$dir"
cmake --preset "$preset" >/dev/null
echo "fuzz: building the targets (preset $preset; log: $dir/build.log)"
cmake --build --preset "$preset" -j "${JOBS:-$(nproc)}" >"$dir/build.log" 2>&1 || { tail -40 "$dir/build.log" >&2; exit 1; }

# Seeds: real outputs of two short runs (the default dam break coarsened, and a 1 m tank whose
# files are small, so mutations are cheap), the built-in cases, and every kept regression input.
for run in dam_break tiny; do
  out=$dir/seed_run/$run
  [ -f "$out/checkpoint.bin" ] && continue
  rm -rf "$out"
  if [ "$run" = dam_break ]; then
    "$sluice" run -q --threads 1 --set time.end=0.05 --set domain.dx=0.4 -o "$out" >/dev/null
  else
    "$sluice" run -q --threads 1 --set time.end=0.05 --set domain.dx=0.25 --set tank.width=1 --set tank.height=1 \
      --set 'water[0].max=[1.0, 0.5]' --set 'water[1].min=[0.0, 0.5]' --set 'water[1].max=[0.5, 0.75]' \
      --set case.name=tiny -o "$out" >/dev/null
  fi
done
mkdir -p "$dir"/corpus_case "$dir"/corpus_checkpoint "$dir"/corpus_frame "$dir"/corpus_mesh
cp cases/*.toml "$dir"/corpus_case/
cp cases/meshes/* "$dir"/corpus_mesh/
for run in dam_break tiny; do
  cp "$dir/seed_run/$run/checkpoint.bin" "$dir/corpus_checkpoint/seed_$run.bin"
  for f in "$dir/seed_run/$run"/frames/*.npz; do cp "$f" "$dir/corpus_frame/seed_${run}_$(basename "$f")"; done
done
for t in case checkpoint frame mesh; do
  if compgen -G "tests/fuzz_regressions/$t/*" >/dev/null; then cp tests/fuzz_regressions/$t/* "$dir/corpus_$t/"; fi
done

export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1}
export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$PWD/fuzz/lsan.supp}
declare -A dict=([case]=fuzz/case.dict [checkpoint]=fuzz/checkpoint.dict [frame]=fuzz/npz.dict [mesh]=fuzz/mesh.dict)
failed=()
for t in $targets; do
  mkdir -p "$dir/artifacts/$t"
  log=$dir/fuzz_$t.log
  echo "fuzz: $t for ${seconds} s (log: $log)"
  # One process (no -jobs/-workers): the machine is shared. -timeout: a single input taking over
  # 10 s is a hang; -rss_limit_mb: more than 2 GiB is a runaway allocation.
  if [ "$seconds" = 0 ]; then run=(-runs=0); else run=(-max_total_time="$seconds"); fi
  if "$bin/fuzz_$t" "${run[@]}" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
      -dict="${dict[$t]}" -artifact_prefix="$dir/artifacts/$t/" "$dir/corpus_$t" >"$log" 2>&1; then
    grep -E '^(Done|stat::number_of_executed_units|stat::peak_rss_mb)' "$log" | sed "s/^/fuzz: $t: /" || true
    grep -E '^#[0-9]+.*(DONE|cov:)' "$log" | tail -1 | sed "s/^/fuzz: $t: /" || true
  else
    echo "fuzz: $t FAILED; the end of $log:" >&2
    tail -40 "$log" >&2
    ls "$dir/artifacts/$t" >&2
    failed+=("$t")
  fi
done
if [ ${#failed[@]} -ne 0 ]; then
  echo "fuzz: findings in: ${failed[*]} (inputs in $dir/artifacts/)" >&2
  exit 1
fi
echo "fuzz: no findings"
