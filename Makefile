# SPDX-License-Identifier: Apache-2.0
# The README's two commands: `make demo` and `make test`. Each installs what is missing first.
BUILD_DIR ?= build
ASAN_DIR ?= build-asan
JOBS ?= $(shell nproc)
CMAKE_FLAGS ?= -DCMAKE_BUILD_TYPE=Release
DEMO_OUT ?= out/demo

.PHONY: all deps configure build test test-slurm demo demo-all bench test-asan test-asan-full fuzz format clean

all: build

deps:
	@bash scripts/install-deps.sh

$(BUILD_DIR)/CMakeCache.txt: | deps
	cmake -S . -B $(BUILD_DIR) $(CMAKE_FLAGS)

configure: deps $(BUILD_DIR)/CMakeCache.txt

build: configure
	cmake --build $(BUILD_DIR) -j $(JOBS)

test: build
	cd $(BUILD_DIR) && ctest --output-on-failure -j $(JOBS) -LE slow

# docs/stress.md's Slurm recipe on a one-node Slurm started here (needs root; installs munge,
# slurmctld, slurmd, slurm-client and jq). Skips, visibly, where Slurm cannot start, unless
# MORPHMILL_REQUIRE_SLURM=1 (as in .ci/run).
test-slurm: build
	bash scripts/slurm-local.sh install || echo "test-slurm: Slurm packages not installed (above); the test says whether it can run"
	cd $(BUILD_DIR) && MORPHMILL_SLURM_TEST=1 ctest --output-on-failure -L slurm

# Builds only the program (not the tests and benchmarks), then verifies two bundled examples into
# out/demo in seconds; demo-all adds the other three CAMotics projects (minutes).
demo: configure
	cmake --build $(BUILD_DIR) -j $(JOBS) --target morphmill
	bash scripts/demo.sh $(BUILD_DIR)/apps/morphmill $(DEMO_OUT)

demo-all: configure
	cmake --build $(BUILD_DIR) -j $(JOBS) --target morphmill
	bash scripts/demo.sh $(BUILD_DIR)/apps/morphmill $(DEMO_OUT) --all

bench: build
	bash scripts/bench.sh $(BUILD_DIR)

# AddressSanitizer + UndefinedBehaviorSanitizer. `make test-asan` (CI) builds and runs the morph
# library's tests: the guarded file reading and writing, the G-code reader and the generator.
# `make test-asan-full` builds and runs every suite.
ASAN_TARGETS ?= morph_tests
ASAN_CTEST ?= -L morph -LE slow
# Extra CMake options of the sanitizer build, e.g. -DCMAKE_CXX_COMPILER_LAUNCHER=ccache.
ASAN_CMAKE_FLAGS ?=
test-asan: deps
	cmake -S . -B $(ASAN_DIR) -DCMAKE_BUILD_TYPE=RelWithDebInfo -DMORPHMILL_SANITIZE=ON -DMORPHMILL_BUILD_BENCHMARKS=OFF $(ASAN_CMAKE_FLAGS)
	cmake --build $(ASAN_DIR) -j $(JOBS) --target $(ASAN_TARGETS)
	cd $(ASAN_DIR) && LSAN_OPTIONS=suppressions=$(CURDIR)/tests/sanitizer/lsan.supp ctest --output-on-failure -j $(JOBS) $(ASAN_CTEST)

test-asan-full:
	$(MAKE) test-asan ASAN_TARGETS=all ASAN_CTEST="-LE slow"

# libFuzzer harnesses (fuzz/, clang), each run for FUZZ_SECONDS: make fuzz FUZZ_SECONDS=3600
FUZZ_SECONDS ?= 60
fuzz:
	MORPHMILL_EXTRA_PACKAGES="clang libclang-rt-14-dev" bash scripts/install-deps.sh
	bash scripts/fuzz.sh $(FUZZ_SECONDS)

format:
	find morph vdb_ref raytest apps tests -name '*.cpp' -o -name '*.h' | xargs clang-format -i

clean:
	rm -rf $(BUILD_DIR) $(ASAN_DIR) build-fuzz
