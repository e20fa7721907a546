# Thin wrappers over the CMake presets (CMakePresets.json).
# Every target first makes sure the Debian packages are there.
JOBS ?= $(shell nproc)
export CMAKE_BUILD_PARALLEL_LEVEL ?= $(JOBS)
export CTEST_PARALLEL_LEVEL ?= $(JOBS)

.PHONY: all deps build deb demo test test-release test-asan test-fuzz test-arm64 fuzz bench clean \
        stage-build-release stage-build-asan stage-build-arm64 stage-build-fuzz \
        stage-tests-release stage-tests-asan stage-tests-arm64 stage-tests-fuzz

all: build

deps:
	@scripts/install-deps

build: deps
	cmake --preset release
	cmake --build --preset release

# The Debian package of this machine's architecture (amd64 here, arm64 on a
# Pi): build/release/spinewatch_<version>-1_<arch>.deb; on any other machine
# also the arm64 one, cross-built: build/arm64/spinewatch_<version>-1_arm64.deb.
# Builds only what it packages (docs/hardware.md, "Installing from the package").
HOST_ARCH := $(shell dpkg --print-architecture 2>/dev/null)

deb: deps
	cmake --preset release
	cmake --build --preset release --target spinewatchd spinewatch
	cpack --config build/release/CPackConfig.cmake -B build/release
ifneq ($(HOST_ARCH),arm64)
	cmake --preset arm64
	cmake --build --preset arm64 --target spinewatchd spinewatch
	cpack --config build/arm64/CPackConfig.cmake -B build/arm64
endif

# The main job on the embedded default: see README.md, "What the demo shows".
demo: build
	scripts/demo

# Every stage (release, ASan+UBSan, arm64, fuzz), as CI runs it: two lanes
# (make -j2). One builds the presets one after another at nice 19, each
# beside the previous stage's tests; the other runs each stage's tests at
# normal priority once its build is done, one stage at a time. A stage's
# tests leave about a tenth of the two cores idle (processes starting,
# waits on a clock or a broker), which the next build takes. The fuzz stage
# is last: its tests, the shortest, are the only ones nothing builds beside.
# docs/testing.md, "How make test runs".
test: deps
	@$(MAKE) --no-print-directory -j2 stage-tests-fuzz

stage-build-release:
	@scripts/stage build release
stage-build-asan: stage-build-release
	@scripts/stage build asan
stage-build-arm64: stage-build-asan
	@scripts/stage build arm64
stage-build-fuzz: stage-build-arm64
	@scripts/stage build fuzz

stage-tests-release: stage-build-release
	@scripts/stage test release
stage-tests-asan: stage-build-asan stage-tests-release
	@scripts/stage test asan
stage-tests-arm64: stage-build-arm64 stage-tests-asan
	@scripts/stage test arm64
stage-tests-fuzz: stage-build-fuzz stage-tests-arm64
	@scripts/stage test fuzz

# One stage alone: configure, build and tests, in the foreground.
test-release:
	cmake --workflow --preset release

test-asan:
	cmake --workflow --preset asan

# The libFuzzer harnesses (tests/fuzz), clang-14: each fuzzes a bounded
# time under ctest (docs/testing.md, "Fuzzing").
test-fuzz:
	cmake --workflow --preset fuzz

# The libraries, spinewatchd, spinewatch and the unit tests cross-built for
# aarch64 against the arm64 sysroot (scripts/arm64-sysroot); the tests
# labelled arm64 run under qemu-user (docs/testing.md, "arm64").
test-arm64:
	cmake --workflow --preset arm64

# The same harnesses run long: 10^6 executions each, one at a time.
fuzz: deps
	scripts/fuzz

bench: build
	scripts/bench

clean:
	rm -rf build
