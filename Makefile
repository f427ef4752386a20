# The two commands README promises: `make demo` and `make test`. Both install what is missing,
# configure, build (Release, -j2) and run. `make demo` builds only what the demo runs (the library and
# the command: Ninja target mtcal); `make test` builds everything it tests (all: tests, fuzz replays,
# the Python module, benchmarks); `make bench` only the benchmarks (docs/building.md, build times).
BUILD ?= build
JOBS ?= 2
CMAKE_EXTRA_FLAGS ?=
# Unity batches (MTCAL_UNITY, docs/building.md "Unity builds"): the fastest build from nothing (a fresh
# clone, CI: 43 % less CPU for the library and command), but touching one unit recompiles its batch of 8. A contributor who
# rebuilds after every edit sets UNITY=OFF (`make test UNITY=OFF`): one unit rebuilds alone.
UNITY ?= ON
# The compilers: `make test CXX=clang++ CC=clang BUILD=build-clang` builds with Debian's clang
# (scripts/install-deps installs it when CXX names clang). Without CXX/CC, CMake picks its default.
COMPILERS = $(if $(filter default,$(origin CXX)),,-DCMAKE_CXX_COMPILER=$(CXX)) \
            $(if $(filter default,$(origin CC)),,-DCMAKE_C_COMPILER=$(CC))
MTCAL = $(BUILD)/apps/mtcal/mtcal

.PHONY: all deps configure build demo test build-times test-linuxcnc test-loop bench test-sanitize fuzz fuzz-run format clean

all: build

deps:
	CXX="$(CXX)" scripts/install-deps $(DEPS_FLAGS)

configure: deps
	cmake -S . -B $(BUILD) -G Ninja -DCMAKE_BUILD_TYPE=Release -DMTCAL_UNITY=$(UNITY) $(COMPILERS) $(CMAKE_EXTRA_FLAGS)

build: configure
	cmake --build $(BUILD) -j $(JOBS)

demo: configure
	cmake --build $(BUILD) -j $(JOBS) --target mtcal
	scripts/demo $(MTCAL)

# ctest -j: every test, none left out by label (the slow groups have labels only to pick them by
# hand: `ctest -L browser`, `ctest -LE 'browser|linuxcnc|postgresql'`; docs/building.md); a test
# that cannot run here (no Chromium, no rs274) is listed SKIPPED with its reason.
test: build
	ctest --test-dir $(BUILD) --output-on-failure -j $(JOBS)

# The compensation that `mtcal compensate --format linuxcnc` writes, loaded by the real controller:
# installs Debian's linuxcnc-uspace (only this target does: DEPS_FLAGS reaches `deps` through the
# prerequisites, one apt-get update) and runs LinuxCNC headless, about 1.5 minutes
# (tests/linuxcnc/run, docs/compensation-linuxcnc-test.md).
test-linuxcnc: DEPS_FLAGS = --linuxcnc
# Then the kinematics module of --format linuxcnc-kins built with halcompile (linuxcnc-uspace-dev) and
# run on the four example machines with its COMP_FILE reversal tables loaded, and G43 from a tool
# table on three of them, about 7 minutes on
# 2 cores (tests/linuxcnc/run-kins, docs/compensation-linuxcnc-kins.md).
# Then the probing program of `mtcal plan` run in LinuxCNC with the simulated probe of
# `mtcal linuxcnc-probe` (halcompile), its log read back and identified against the truth, and a
# probe that never trips, about 2 minutes (tests/linuxcnc/run-probe, docs/planning.md).
# Then the closed loop of examples/loop/loop.sh on the RRTTT, one seed: plan --locate -> LinuxCNC
# (nominal kinematics module, simulated probe of a secret truth: location errors, an ECC table, the
# sphere 1.8 mm from its rough position) -> probe-log --locate -> plan -> LinuxCNC -> identify ->
# compensate --format linuxcnc-kins -> LinuxCNC with the module, the same program and 200 random
# poses -> history diff, the figures checked against the truth, and three faults (a log cut short,
# a truth the model cannot reach, a module that does not converge mid-program), about 4 minutes
# (tests/linuxcnc/run-loop, docs/workflows.md).
# Then LinuxCNC's example programs through its interpreter rs274 (tests/linuxcnc/ncfiles/run,
# docs/gcode.md), which `make test` skips when linuxcnc-uspace is not installed.
test-linuxcnc: build
	tests/linuxcnc/run $(MTCAL)
	tests/linuxcnc/run-kins $(MTCAL)
	tests/linuxcnc/run-probe $(MTCAL)
	tests/linuxcnc/run-loop $(MTCAL)
	MTCAL_REQUIRE_RS274=1 tests/linuxcnc/ncfiles/run $(MTCAL)

# The closed loop's other cases, nightly-style (not in CI): the RRTTT with a second seed (another
# sphere position, other random poses) and a probe that never trips in LinuxCNC (the locating
# program's first touch), and the second machine, the HU40T, with its location errors and C's
# positioning error as a table (tests/linuxcnc/run-loop, docs/workflows.md "The closed loop").
test-loop: DEPS_FLAGS = --linuxcnc
test-loop: build
	tests/linuxcnc/run-loop $(MTCAL) --case rrttt-seed2 --case hu40t-seed1

# The benchmarks, then the ratios against their baselines of the same run (bench/ratios.py) and
# `eval --grid` against the grid-aware numpy peer (bench/grid_peer.py); docs/performance.md.
bench: configure
	cmake --build $(BUILD) -j $(JOBS) --target mtcal_bench mtcal_grid_factors mtcal
	$(BUILD)/bench/mtcal_bench --benchmark_min_time=0.5 --benchmark_out=$(BUILD)/bench.json
	/usr/bin/python3 bench/ratios.py $(BUILD)/bench.json
	/usr/bin/python3 bench/grid_peer.py --build $(BUILD)

# The suite under AddressSanitizer + UndefinedBehaviorSanitizer (CMake preset "asan"; with
# CXX=clang++ CC=clang the preset "asan-clang", built in build-asan-clang).
SANITIZE_PRESET = $(if $(findstring clang,$(CXX)),asan-clang,asan)
test-sanitize: deps
	cmake --preset $(SANITIZE_PRESET) $(CMAKE_EXTRA_FLAGS)
	cmake --build --preset $(SANITIZE_PRESET)
	ctest --preset $(SANITIZE_PRESET)

# The readers' libFuzzer targets (tests/fuzz, preset "fuzz": Debian's clang, ASan+UBSan) in
# build-fuzz; `make fuzz-run FUZZ_SECONDS=600` runs each in turn (scripts/run-fuzzers, logs in
# build-fuzz/fuzz-logs). docs/reliability.md.
FUZZ_SECONDS ?= 60
fuzz: CXX = clang++
fuzz: CC = clang
fuzz: deps
	cmake --preset fuzz $(CMAKE_EXTRA_FLAGS)
	cmake --build --preset fuzz

fuzz-run: fuzz
	scripts/run-fuzzers build-fuzz/tests/fuzz $(FUZZ_SECONDS) build-fuzz/fuzz-logs

# Compile-seconds per unit of the last build (scripts/build-times; docs/building.md).
build-times:
	scripts/build-times $(BUILD)

# Reformat every C++ file git knows with .clang-format (clang-format 14, Debian's clang-format).
format:
	git ls-files '*.cpp' '*.hpp' '*.h' | xargs clang-format -i

clean:
	rm -rf $(BUILD) build-asan build-asan-clang build-fuzz
