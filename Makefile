# The two commands README promises: `make demo` and `make test`. Both install what is missing,
# configure, build (Release, -j2) and run.
BUILD ?= build
ASAN_BUILD ?= build-asan
JOBS ?= 2
CMAKE_EXTRA_FLAGS ?=
MTCAL = $(BUILD)/apps/mtcal/mtcal

.PHONY: all deps configure build demo test bench test-sanitize clean

all: build

deps:
	scripts/install-deps

configure: deps
	cmake -S . -B $(BUILD) -G Ninja -DCMAKE_BUILD_TYPE=Release $(CMAKE_EXTRA_FLAGS)

build: configure
	cmake --build $(BUILD) -j $(JOBS)

demo: build
	scripts/demo $(MTCAL)

test: build
	ctest --test-dir $(BUILD) --output-on-failure -j $(JOBS)

bench: build
	$(BUILD)/bench/mtcal_bench --benchmark_min_time=0.5

test-sanitize: deps
	cmake -S . -B $(ASAN_BUILD) -G Ninja -DCMAKE_BUILD_TYPE=Debug -DMTCAL_SANITIZE=ON -DMTCAL_BUILD_BENCH=OFF $(CMAKE_EXTRA_FLAGS)
	cmake --build $(ASAN_BUILD) -j $(JOBS)
	ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
	  ctest --test-dir $(ASAN_BUILD) --output-on-failure -j $(JOBS)

clean:
	rm -rf $(BUILD) $(ASAN_BUILD)
