# The README's two commands: `make demo` and `make test`. Each installs what is missing first.
BUILD_DIR ?= build
ASAN_DIR ?= build-asan
JOBS ?= $(shell nproc)
CMAKE_FLAGS ?= -DCMAKE_BUILD_TYPE=Release
DEMO_OUT ?= out/demo

.PHONY: all deps configure build test test-slurm demo bench test-asan format clean

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

demo: build
	bash scripts/demo.sh $(BUILD_DIR)/apps/morphmill $(DEMO_OUT)

bench: build
	bash scripts/bench.sh $(BUILD_DIR)

test-asan: deps
	cmake -S . -B $(ASAN_DIR) -DCMAKE_BUILD_TYPE=RelWithDebInfo -DMORPHMILL_SANITIZE=ON -DMORPHMILL_BUILD_BENCHMARKS=OFF
	cmake --build $(ASAN_DIR) -j $(JOBS)
	cd $(ASAN_DIR) && ctest --output-on-failure -j $(JOBS) -LE slow

format:
	find morph vdb_ref raytest apps tests -name '*.cpp' -o -name '*.h' | xargs clang-format -i

clean:
	rm -rf $(BUILD_DIR) $(ASAN_DIR)
