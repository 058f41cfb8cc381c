# The two commands of the README's quick start, and a few more.
#   make demo   installs dependencies, builds (Release), renders the default scene
#   make test   installs dependencies, builds, runs every test
BUILD ?= build/release
ASAN_BUILD ?= build/asan
JOBS ?= $(shell nproc)
OUT ?= out

.PHONY: demo test build deps asan bench clean

deps:
	@scripts/install-deps.sh

$(BUILD)/build.ninja:
	cmake -S . -B $(BUILD) -G Ninja -DCMAKE_BUILD_TYPE=Release

build: deps $(BUILD)/build.ninja
	cmake --build $(BUILD) -j $(JOBS)

demo: build
	@mkdir -p $(OUT)
	$(BUILD)/oovr scene-info --scene courtyard
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

bench: build
	$(BUILD)/bench/oovr-bench

clean:
	rm -rf build $(OUT)
