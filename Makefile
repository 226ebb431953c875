# dhdr: two commands for a fresh Debian 12 machine.
#   make demo   install what is missing, build the tools (Release), run the pipeline on the Cornell box
#   make test   install what is missing, build, run the test suite (ctest)
#   make sanitize  the same suite built with AddressSanitizer + UndefinedBehaviorSanitizer
#   make fuzz      build the libFuzzer targets (clang) and run each for FUZZ_SECONDS (60)
#   make golden    regenerate the golden images of the demo chain (testdata/golden)

BUILD ?= build
JOBS  ?= $(shell nproc)
BUILD_TYPE ?= Release

.PHONY: all deps configure build test sanitize fuzz golden demo bench format clean

all: build

deps:
	@bash scripts/install-deps.sh

configure: deps
	@cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=$(BUILD_TYPE) >/dev/null

build: configure
	@cmake --build $(BUILD) -j $(JOBS)

# The Python tests run as one ctest test (pytest fails when it collects none); a build that
# has lost them fails here rather than passing without them.
test: build
	@cd $(BUILD) && ctest -N -R '^Python\.pytest$$' | grep -q 'Total Tests: 1' || \
		{ echo "make test: the Python tests (Python.pytest) are not registered" >&2; exit 1; }
	@cd $(BUILD) && ctest --output-on-failure -j $(JOBS)

# The suite under AddressSanitizer + UndefinedBehaviorSanitizer (docs/development.md).
sanitize: deps
	@cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DDHDR_SANITIZE=ON >/dev/null
	@cmake --build build-asan -j $(JOBS)
	@cd build-asan && ASAN_OPTIONS=detect_leaks=0:abort_on_error=0 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 ctest --output-on-failure -j $(JOBS)

# The libFuzzer targets of fuzz/, built with clang in build-fuzz/, FUZZ_SECONDS (60) each
# (docs/development.md, "Fuzzing"); fails when any target crashed.
fuzz:
	@bash scripts/fuzz.sh

# Regenerates testdata/golden from the current build: only after a change meant to alter the
# pictures, and looked at before committing (docs/development.md).
golden: build
	@bash tests/golden/run.sh $(BUILD)/apps --update

# The tools only (not the tests): the first picture comes after the dependencies and the
# libraries and tools compile, not after the whole suite.
demo: configure
	@cmake --build $(BUILD) --target dhdr-tools -j $(JOBS)
	@bash scripts/demo.sh $(BUILD)/apps out/demo

bench: build
	@python3 bench/pipeline.py --bin $(BUILD)/apps
	@python3 bench/shadows.py --bin $(BUILD)/apps
	@python3 bench/ibl.py --bin $(BUILD)/apps
	@python3 bench/deep.py --bin $(BUILD)/apps
	@python3 bench/probes.py --bin $(BUILD)/apps
	@python3 bench/false_shadows.py --bin $(BUILD)/apps
	@python3 bench/farm.py --bin $(BUILD)/apps
	@$(BUILD)/dhdr-bench-occlusion testdata/cornell_box.gltf

format:
	@clang-format -i $$(git ls-files '*.h' '*.cpp')

clean:
	@rm -rf $(BUILD) build-asan out
