# The two commands of the README's quick start, and a few more.
#   make demo   installs dependencies, builds (Release), compares every scheme on the default scene
#   make test   installs dependencies, builds, runs every test
BUILD ?= build/release
ASAN_BUILD ?= build/asan
JOBS ?= $(shell nproc)
OUT ?= out

FUZZ_BUILD ?= build/fuzz
FUZZ_SECONDS ?= 60

.PHONY: demo test build deps asan bench fuzz clean

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

# AddressSanitizer + UndefinedBehaviorSanitizer build, all tests.
asan: deps
	cmake -S . -B $(ASAN_BUILD) -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DOOVR_SANITIZE=ON -DOOVR_BUILD_BENCH=OFF
	cmake --build $(ASAN_BUILD) -j $(JOBS)
	ASAN_OPTIONS=detect_leaks=1 LSAN_OPTIONS=suppressions=$(CURDIR)/tests/lsan.supp \
	  ctest --test-dir $(ASAN_BUILD) --output-on-failure -j $(JOBS)

# libFuzzer targets for the BSP parser and the SGI decoder, each run for
# FUZZ_SECONDS from seeds written by oovr-fuzz-seeds; a crash fails the target.
fuzz: deps
	cmake -S . -B $(FUZZ_BUILD) -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ \
	  -DOOVR_FUZZ=ON -DOOVR_BUILD_TESTS=OFF -DOOVR_BUILD_BENCH=OFF -DOOVR_BUILD_REFERENCE=OFF
	cmake --build $(FUZZ_BUILD) -j $(JOBS) --target fuzz_bsp fuzz_sgi fuzz_q3_shader oovr-fuzz-seeds
	$(FUZZ_BUILD)/fuzz/oovr-fuzz-seeds $(FUZZ_BUILD)/corpus
	$(FUZZ_BUILD)/fuzz/fuzz_bsp $(FUZZ_BUILD)/corpus/bsp -max_total_time=$(FUZZ_SECONDS) -max_len=65536 -rss_limit_mb=2048 -print_final_stats=1
	$(FUZZ_BUILD)/fuzz/fuzz_sgi $(FUZZ_BUILD)/corpus/sgi -max_total_time=$(FUZZ_SECONDS) -max_len=65536 -rss_limit_mb=2048 -print_final_stats=1
	$(FUZZ_BUILD)/fuzz/fuzz_q3_shader $(FUZZ_BUILD)/corpus/shader -max_total_time=$(FUZZ_SECONDS) -max_len=16384 -rss_limit_mb=2048 -print_final_stats=1

bench: build
	$(BUILD)/bench/oovr-bench

clean:
	rm -rf build $(OUT)
