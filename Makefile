# moreau: the two commands of the quick start are `make demo` and `make test`.
JOBS     ?= 2
BUILD    ?= build/release
ASAN     ?= build/asan
OUT      ?= out
PYTHON   := /usr/bin/python3
MOREAU   := $(BUILD)/moreau
CMAKE_FLAGS := -DPython_EXECUTABLE=$(PYTHON) -DMOREAU_PYTHON=$(PYTHON)

.PHONY: all deps build test test-release test-asan demo bench format clean

all: build

deps:
	@./scripts/install-deps

build: deps
	@cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release $(CMAKE_FLAGS) > /dev/null
	@cmake --build $(BUILD) -j $(JOBS)

# Every test in Release, then the unit tests again under AddressSanitizer + UBSan.
test: test-release test-asan

test-release: build
	@cd $(BUILD) && ctest --output-on-failure -j $(JOBS)

test-asan: deps
	@cmake -S . -B $(ASAN) -DCMAKE_BUILD_TYPE=RelWithDebInfo -DMOREAU_SANITIZE=ON \
	  -DMOREAU_BUILD_BENCH=OFF $(CMAKE_FLAGS) > /dev/null
	@cmake --build $(ASAN) -j $(JOBS) --target moreau_tests
	@ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
	  $(ASAN)/moreau_tests --gtest_brief=1 --gtest_filter=-*Slow*

# The flagship examples: studies and figures under out/.
demo: build
	@mkdir -p $(OUT)
	$(MOREAU) study examples/sliding.toml --methods pbd,pngs,pgs,penalty:100,penalty:1000 \
	  --h 0.4,0.2,0.1,0.05,0.025,0.0125,0.00625,0.003125,0.0015625,0.00078125,0.000390625 \
	  --out $(OUT)/sliding
	$(MOREAU) study examples/sliding_d5.toml --methods pbd,pngs,pgs,penalty:1000 \
	  --h 0.2,0.1,0.05,0.025,0.0125,0.00625,0.003125,0.0015625,0.00078125 --out $(OUT)/sliding_d5
	$(MOREAU) study examples/disks.toml --methods pbd,pngs,pgs,penalty:100,penalty:1000 \
	  --h 0.1,0.05,0.025,0.0125,0.00625,0.003125,0.0015625,0.00078125 --out $(OUT)/disks
	$(MOREAU) run examples/disks.toml --out $(OUT)/disks_run
	@echo "demo: figures are in $(OUT)/ (see README.md for how to read them)"

bench: build
	$(BUILD)/pbd_bench

format:
	@clang-format -i $$(git ls-files '*.h' '*.cpp')

clean:
	rm -rf build $(OUT)
