# The two commands of the README's quick start, and a few more.
#   make demo   installs dependencies, builds (Release), compares every scheme on the default scene
#   make test   installs dependencies, builds, runs every test
SHELL := /bin/bash
BUILD ?= build/release
JOBS ?= $(shell nproc)
OUT ?= out

# One clang build serves `make asan` and `make fuzz`: AddressSanitizer and
# UndefinedBehaviorSanitizer (undefined behaviour fatal) on every object, with
# libFuzzer's coverage, so that CI compiles the instrumented code once.
SAN_BUILD ?= build/sanitize
ASAN_CTEST_ARGS ?=
FUZZ_SECONDS ?= 60

.PHONY: demo test build deps asan bench fuzz format format-check clean

deps:
	@scripts/install-deps.sh

$(BUILD)/build.ninja:
	cmake -S . -B $(BUILD) -G Ninja -DCMAKE_BUILD_TYPE=Release

build: deps $(BUILD)/build.ninja
	cmake --build $(BUILD) -j $(JOBS)

# The main job: every scheme on the default scene, normalised to the baseline.
demo: build
	@mkdir -p $(OUT)
	$(BUILD)/oovr compare --scene courtyard --json $(OUT)/compare-courtyard.json
	$(BUILD)/oovr render --scene courtyard --out $(OUT)/courtyard.png

test: build
	ctest --test-dir $(BUILD) --output-on-failure -j $(JOBS)
	@scripts/validation-summary.sh $(BUILD)

# Line tables only for debug information: what the sanitizers' reports need
# (file, line, inlined frames), in a little less compile time than -g
# (paper_doc.cpp 29 s against 31 to 35).
$(SAN_BUILD)/build.ninja:
	cmake -S . -B $(SAN_BUILD) -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ \
	  "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O2 -gline-tables-only -DNDEBUG" \
	  -DOOVR_SANITIZE=ON -DOOVR_FUZZ=ON -DOOVR_BUILD_BENCH=OFF

# Every test under the sanitizers (ASAN_CTEST_ARGS narrows them: CI passes
# "-LE long", docs/reliability.md). Leaks are errors, Mesa's excepted.
asan: deps $(SAN_BUILD)/build.ninja
	cmake --build $(SAN_BUILD) -j $(JOBS)
	ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 LSAN_OPTIONS=suppressions=$(CURDIR)/tests/lsan.supp \
	  ctest --test-dir $(SAN_BUILD) --output-on-failure -j $(JOBS) $(ASAN_CTEST_ARGS)

# libFuzzer targets for every parser oovr owns or guards (BSP, SGI, Quake 3
# shader scripts, configuration, trace cache, model checks, AC3D, TORCS, pk3,
# sweep files and run records, hardware data),
# each run for FUZZ_SECONDS from seeds written by oovr-fuzz-seeds; a crash,
# a hang (-timeout) or a blown memory limit fails the target.
FUZZ_TARGETS ?= bsp sgi q3_shader config trace model ac3d torcs pk3 sweep hardware collect sweep_name apitrace
fuzz: deps $(SAN_BUILD)/build.ninja
	cmake --build $(SAN_BUILD) -j $(JOBS) --target $(addprefix fuzz_,$(FUZZ_TARGETS)) oovr-fuzz-seeds
	$(SAN_BUILD)/fuzz/oovr-fuzz-seeds $(SAN_BUILD)/corpus $(CURDIR)
	@for t in $(FUZZ_TARGETS); do \
	  dir=$$t; [ $$t = q3_shader ] && dir=shader; \
	  echo "== fuzz_$$t ($(FUZZ_SECONDS) s)"; \
	  UBSAN_OPTIONS=print_stacktrace=1 LSAN_OPTIONS=suppressions=$(CURDIR)/tests/lsan.supp $(SAN_BUILD)/fuzz/fuzz_$$t $(SAN_BUILD)/corpus/$$dir -max_total_time=$(FUZZ_SECONDS) -max_len=65536 \
	    -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 2>&1 | grep -E 'stat::number_of_executed_units|ERROR|SUMMARY|Done' ; \
	  [ $${PIPESTATUS[0]} -eq 0 ] || exit 1; \
	done

# The C++ layout (.clang-format): format applies it, format-check lists what differs.
format:
	@scripts/check-format.sh --fix
format-check:
	@scripts/check-format.sh

bench: build
	$(BUILD)/bench/oovr-bench

clean:
	rm -rf build $(OUT)
