# The two commands: `make run` and `make test`. Everything else is a convenience.
BUILD_DIR ?= build/release
JOBS ?= $(shell nproc)

.PHONY: all setup configure build build-sluice run test check test-all bench asan fuzz docs clean

all: build

setup:
	@bash scripts/setup.sh

configure: setup
	@cmake --preset release >/dev/null

# Everything: the program, the tests and the benchmarks.
build: configure
	@cmake --build --preset release -j $(JOBS)

# The program alone: what `make run` needs.
build-sluice: configure
	@cmake --build --preset release -j $(JOBS) --target sluice

run: build-sluice
	./$(BUILD_DIR)/sluice run -o out/dam_break --render speed

test: build
	ctest --preset release -j $(JOBS) --label-exclude long

# The edit-compile-test loop: the unit tests and the smoke tests (every built-in case stepped a few
# times), built and run alone.
check: configure
	@cmake --build --preset release -j $(JOBS) --target tests_unit tests_smoke
	ctest --preset release -j $(JOBS) --label-regex '^(unit|smoke)$$'

# Longer physics runs (the full default case, soak runs): see docs/hardening.md.
test-all: build
	ctest --preset release -j $(JOBS)

bench: configure
	@cmake --build --preset release -j $(JOBS) --target sluice-bench-run
	./$(BUILD_DIR)/sluice-bench-run --csv bench/results.csv

# The tests under AddressSanitizer + UBSan. ASAN_LABELS (labels joined by |) builds and runs only those
# labels' tests: CI runs `make asan ASAN_LABELS='unit|cli|io|mpi'` (see .ci/run).
ASAN_LABELS ?=
asan: setup
	@cmake --preset asan >/dev/null
	@cmake --build --preset asan -j $(JOBS) $(if $(ASAN_LABELS),--target $(patsubst %,tests_%,$(subst |, ,$(ASAN_LABELS))))
	ctest --preset asan -j $(JOBS) --label-exclude long $(if $(ASAN_LABELS),--label-regex '^($(ASAN_LABELS))$$')

# libFuzzer on the four input parsers (case files, checkpoints, frames, meshes), FUZZ_SECONDS each, one after
# another (FUZZ_TARGETS, FUZZ_PRESET: see docs/hardening.md and scripts/fuzz.sh).
FUZZ_SECONDS ?= 60
fuzz: build
	@bash scripts/setup.sh fuzz
	FUZZ_SECONDS=$(FUZZ_SECONDS) bash scripts/fuzz.sh

# The documentation site, build/docs/index.html: Sphinx with MyST Markdown, warnings as errors. The case-file
# reference and the commands' options are generated from the program (`sluice keys --json`, `--help`).
docs: build-sluice
	SLUICE_BIN=$(abspath $(BUILD_DIR))/sluice sphinx-build -W --keep-going -a -b html docs build/docs
	@echo "docs: build/docs/index.html"

clean:
	rm -rf build
