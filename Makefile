# The two commands: `make run` and `make test`. Everything else is a convenience.
BUILD_DIR ?= build/release
JOBS ?= $(shell nproc)

.PHONY: all setup build run test test-all bench asan clean

all: build

setup:
	@bash scripts/setup.sh

build: setup
	@cmake --preset release >/dev/null
	@cmake --build --preset release -j $(JOBS)

run: build
	./$(BUILD_DIR)/sluice run -o out

test: build
	ctest --preset release -j $(JOBS) --label-exclude long

# Longer physics runs (the full default case, soak runs): see README.
test-all: build
	ctest --preset release -j $(JOBS)

bench: build
	./$(BUILD_DIR)/sluice-bench-run --csv bench/results.csv

asan: setup
	@cmake --preset asan >/dev/null
	@cmake --build --preset asan -j $(JOBS)
	ctest --preset asan -j $(JOBS) --label-exclude long

clean:
	rm -rf build
