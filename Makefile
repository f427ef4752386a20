# The two commands README promises: `make demo` and `make test`. Both install what is missing,
# configure, build (Release, -j2) and run.
BUILD ?= build
JOBS ?= 2
CMAKE_EXTRA_FLAGS ?=
# The compilers: `make test CXX=clang++ CC=clang BUILD=build-clang` builds with Debian's clang
# (scripts/install-deps installs it when CXX names clang). Without CXX/CC, CMake picks its default.
COMPILERS = $(if $(filter default,$(origin CXX)),,-DCMAKE_CXX_COMPILER=$(CXX)) \
            $(if $(filter default,$(origin CC)),,-DCMAKE_C_COMPILER=$(CC))
MTCAL = $(BUILD)/apps/mtcal/mtcal

.PHONY: all deps configure build demo test test-linuxcnc bench test-sanitize format clean

all: build

deps:
	CXX="$(CXX)" scripts/install-deps $(DEPS_FLAGS)

configure: deps
	cmake -S . -B $(BUILD) -G Ninja -DCMAKE_BUILD_TYPE=Release $(COMPILERS) $(CMAKE_EXTRA_FLAGS)

build: configure
	cmake --build $(BUILD) -j $(JOBS)

demo: build
	scripts/demo $(MTCAL)

test: build
	ctest --test-dir $(BUILD) --output-on-failure -j $(JOBS)

# The compensation that `mtcal compensate --format linuxcnc` writes, loaded by the real controller:
# installs Debian's linuxcnc-uspace (only this target does: DEPS_FLAGS reaches `deps` through the
# prerequisites, one apt-get update) and runs LinuxCNC headless, about 1.5 minutes
# (tests/linuxcnc/run, docs/compensation-linuxcnc-test.md).
test-linuxcnc: DEPS_FLAGS = --linuxcnc
test-linuxcnc: build
	tests/linuxcnc/run $(MTCAL)

# The benchmarks, then the ratios against their baselines of the same run (bench/ratios.py) and
# `eval --grid` against the grid-aware numpy peer (bench/grid_peer.py); docs/performance.md.
bench: build
	$(BUILD)/bench/mtcal_bench --benchmark_min_time=0.5 --benchmark_out=$(BUILD)/bench.json
	/usr/bin/python3 bench/ratios.py $(BUILD)/bench.json
	/usr/bin/python3 bench/grid_peer.py --build $(BUILD)

# The suite under AddressSanitizer + UndefinedBehaviorSanitizer (CMake preset "asan").
test-sanitize: deps
	cmake --preset asan $(CMAKE_EXTRA_FLAGS)
	cmake --build --preset asan
	ctest --preset asan

# Reformat every C++ file git knows with .clang-format (clang-format 14, Debian's clang-format).
format:
	git ls-files '*.cpp' '*.hpp' '*.h' | xargs clang-format -i

clean:
	rm -rf $(BUILD) build-asan
