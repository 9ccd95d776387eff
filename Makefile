# moreau: the two commands of the quick start are `make demo` and `make test`.
JOBS     ?= 2
export OMP_WAIT_POLICY ?= passive
BUILD    ?= build/release
ASAN     ?= build/asan
FUZZ_SECONDS ?= 600
FUZZ_TEST_SECONDS ?= 25
OUT      ?= out
MOCAP_DATA ?= ../shared/data/mocap
PYTHON   := /usr/bin/python3
MOREAU   := $(BUILD)/moreau
CMAKE_FLAGS := -DMOREAU_PYTHON=$(PYTHON) -DMOREAU_UNITY_BUILD=ON

.PHONY: all deps build python test test-build test-release sanitize-build test-asan test-clients crowds-venv test-fuzz fuzz \
        fuzz-build demo abm-results fields-results bench format clean

all: build

deps:
	@./scripts/install-deps

build: deps
	@cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release $(CMAKE_FLAGS) > /dev/null
	@cmake --build $(BUILD) -j $(JOBS)

# The Python package in $(BUILD)/python (use it with PYTHONPATH=$(BUILD)/python, or install it:
# docs/python.md). `build` builds it too when pybind11 is installed.
python: deps
	@cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release $(CMAKE_FLAGS) > /dev/null
	@cmake --build $(BUILD) -j $(JOBS) --target moreau_python

# Every test in Release (tests/python through ctest), the unit tests again under
# AddressSanitizer + UBSan, the client suite (the outputs opened with ParaView, VTK, h5py, numpy,
# ezc3d and Kinetics Toolkit), then each fuzz target for FUZZ_TEST_SECONDS. One make with a pool
# of JOBS jobs (one jobserver) runs the first three and the two builds they need: the Release and
# the sanitizer trees compile at the same time, and each test run starts as soon as its own tree
# is built, so that no core waits for the other tree's last file or the slowest test of another
# run. The fuzz targets run last, alone, for their full time on every core. Any failure fails the
# run.
test: deps
	+@$(MAKE) --no-print-directory -j $(JOBS) POOL=1 test-release test-asan test-clients
	$(run-fuzz)

# `-j JOBS` for one build on its own; nothing when `make test` hands out the jobs (POOL=1).
PARALLEL = $(if $(POOL),,-j $(JOBS))

# What the tests run (the benchmarks are built by `make build`/`make bench`, not by `make test`).
test-build: deps
	@cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release $(CMAKE_FLAGS) > /dev/null
	+@cmake --build $(BUILD) $(PARALLEL) --target moreau_cli moreau_tests moreau_python

define run-release
	@cd $(BUILD) && ctest --output-on-failure -j $(JOBS)
endef
test-release: test-build
	$(run-release)

# The sanitizer build (clang 14, AddressSanitizer + UBSan) in $(ASAN): one library for both the
# unit tests and the fuzz targets (fuzz/); only the parsers' sources that the fuzz targets exercise
# carry libFuzzer's coverage instrumentation (CMakeLists.txt, MOREAU_FUZZ).
# A tree configured earlier with another compiler is started afresh.
SANITIZE_FLAGS := -DCMAKE_BUILD_TYPE=None -DCMAKE_CXX_COMPILER=clang++-14 -DCMAKE_C_COMPILER=clang-14 \
  -DCMAKE_CXX_FLAGS="-O1 -gline-tables-only" -DMOREAU_SANITIZE=ON -DMOREAU_FUZZ=ON \
  -DMOREAU_BUILD_BENCH=OFF
define configure-sanitize
	@if [ -f $(ASAN)/CMakeCache.txt ] && ! grep -q '^CMAKE_CXX_COMPILER:[A-Z]*=.*clang++-14$$' \
	  $(ASAN)/CMakeCache.txt; then rm -rf $(ASAN); fi
	@cmake -S . -B $(ASAN) $(SANITIZE_FLAGS) $(CMAKE_FLAGS) > /dev/null
endef

# The unit tests and the fuzz targets in the sanitizer build.
sanitize-build: deps
	$(configure-sanitize)
	+@cmake --build $(ASAN) $(PARALLEL) --target moreau_tests scenario_fuzz c3d_fuzz sweep_fuzz gaps_fuzz

# The unit tests except *Slow* under the sanitizers, in JOBS GoogleTest shards side by side; the
# log of a failing shard is printed (all logs: $(ASAN)/unit_tests.<shard>.log).
define run-asan
	@pids=; for i in $$(seq 0 $$(($(JOBS) - 1))); do \
	  GTEST_TOTAL_SHARDS=$(JOBS) GTEST_SHARD_INDEX=$$i ASAN_OPTIONS=detect_leaks=1 \
	    UBSAN_OPTIONS=print_stacktrace=1 $(ASAN)/moreau_tests --gtest_brief=1 \
	    --gtest_filter=-*Slow* > $(ASAN)/unit_tests.$$i.log 2>&1 & pids="$$pids $$!"; \
	done; status=0; i=0; for pid in $$pids; do \
	  if wait $$pid; then echo "test-asan: shard $$i: $$(grep -E "^\[ +(PASSED|SKIPPED) +\]" $(ASAN)/unit_tests.$$i.log | tr "\n" " ")"; \
	  else status=1; cat $(ASAN)/unit_tests.$$i.log; fi; i=$$((i + 1)); \
	done; exit $$status
endef
test-asan: sanitize-build
	$(run-asan)

# Outputs opened with the programs people use (tests/clients; needs scripts/install-deps). The
# suite runs under $(PYTHON); the C3D readers of the field, ezc3d and Kinetics Toolkit, are on PyPI
# only: tests/clients/c3d_read.py runs them in CLIENTS_VENV, a virtual environment made here from
# the pins of tests/clients/requirements.txt (test-only: nothing else needs it). It is made once
# (the stamp CLIENTS_VENV/installed) and again when the pins change; when it cannot be made (no
# network) the tests that need it skip, saying so, and the next run tries again. It holds no build
# output, so every BUILD tree shares it.
CLIENTS_VENV ?= build/clients-venv
CLIENTS_PINS := tests/clients/requirements.txt

# $(call make-venv,DIR,PINS,MESSAGE): DIR made afresh from the pins, stamped DIR/installed; when
# pip fails, DIR is removed and MESSAGE printed.
define make-venv
	@rm -rf $(1)
	@if $(PYTHON) -m venv $(1) && $(1)/bin/pip install -q \
	  --disable-pip-version-check --retries 1 --timeout 30 -r $(2); then touch $(1)/installed; \
	else rm -rf $(1); echo "$(3)"; fi
endef

$(CLIENTS_VENV)/installed: $(CLIENTS_PINS)
	$(call make-venv,$(CLIENTS_VENV),$(CLIENTS_PINS),test-clients: $(CLIENTS_VENV) not made \
	  (PyPI unreachable?): the C3D reader tests skip)

# JuPedSim and PedPy (PyPI only) for the side-by-side comparison of the collision-free speed model
# (scripts/crowd_jupedsim.py, docs/crowds.md) and its client test: CROWDS_VENV, made like
# CLIENTS_VENV from the pins of tests/crowds/requirements.txt (benchmark- and test-only); when it
# cannot be made the test skips, saying so. `make crowds-venv` makes it alone.
CROWDS_VENV ?= build/crowds-venv
CROWDS_PINS := tests/crowds/requirements.txt

$(CROWDS_VENV)/installed: $(CROWDS_PINS)
	$(call make-venv,$(CROWDS_VENV),$(CROWDS_PINS),crowds-venv: $(CROWDS_VENV) not made \
	  (PyPI unreachable?): the JuPedSim comparison skips)

crowds-venv: $(CROWDS_VENV)/installed

define run-clients
	@MOREAU_CLI=$(MOREAU) MOREAU_TESTS=$(BUILD)/moreau_tests MOREAU_ROOT=$(CURDIR) \
	  MOREAU_CLIENTS_VENV=$(CLIENTS_VENV) MOREAU_CROWDS_VENV=$(CROWDS_VENV) \
	  $(PYTHON) -m pytest -q -p no:cacheprovider tests/clients
endef
test-clients: test-build $(CLIENTS_VENV)/installed $(CROWDS_VENV)/installed
	$(run-clients)

# libFuzzer targets of the scenario, sweep, gap-list and C3D readers (fuzz/, in the sanitizer build): `make fuzz`
# runs each for FUZZ_SECONDS, `make test` for FUZZ_TEST_SECONDS; a finding fails the run
# (fuzz/run.sh).
fuzz-build: deps
	$(configure-sanitize)
	+@cmake --build $(ASAN) $(PARALLEL) --target scenario_fuzz c3d_fuzz sweep_fuzz gaps_fuzz

fuzz: fuzz-build
	@./fuzz/run.sh $(ASAN) $(FUZZ_SECONDS) $(MOCAP_DATA)

define run-fuzz
	@./fuzz/run.sh $(ASAN) $(FUZZ_TEST_SECONDS) $(MOCAP_DATA)
endef
test-fuzz: fuzz-build
	$(run-fuzz)

# The flagship examples: studies and figures under out/.
demo: build
	@mkdir -p $(OUT)
	$(MOREAU) study examples/sliding.toml --methods pbd,pngs,pgs,penalty:100,penalty:1000,penalty:10000 \
	  --h $(SLIDING_H) --out $(OUT)/sliding
	$(MOREAU) study examples/sliding_d5.toml --methods pbd,pngs,pgs,penalty:10000 \
	  --h $(SLIDING_H) --out $(OUT)/sliding_d5
	$(MOREAU) study examples/disks.toml --methods pbd,pngs,pgs,penalty:100,penalty:1000,penalty:10000 \
	  --h $(DISKS_H) --out $(OUT)/disks
	$(MOREAU) run examples/disks.toml --out $(OUT)/disks_run
	$(MOREAU) run examples/sliding.toml --out $(OUT)/sliding_run
	$(MOREAU) run examples/abm/monolayer.toml --out $(OUT)/abm_monolayer
	$(PYTHON) examples/abm/plot_abm.py count $(OUT)/abm_monolayer/count.png $(OUT)/abm_monolayer/population.csv
	$(PYTHON) examples/abm/plot_abm.py snapshot $(OUT)/abm_monolayer/snapshot.png $(OUT)/abm_monolayer/agents.csv
	$(MOREAU) control examples/control/oscillator_1d.toml --out $(OUT)/oscillator_1d
	$(MOREAU) control examples/control/oscillator_1d.toml --out $(OUT)/oscillator_1d_study \
	  --study-steps 500,1000,1500,2000,2500,3000,3500,4000
	$(MOREAU) control examples/control/arm_2d.toml --out $(OUT)/arm_2d
	$(MOREAU) control examples/control/arm_2d.toml --out $(OUT)/arm_2d_study \
	  --study-steps 32,64,128,256,512,1024,2048,4096
	$(MOREAU) run examples/crowd.toml --out $(OUT)/crowd
	$(MOREAU) run examples/packing3d.toml --out $(OUT)/packing3d
	$(MOREAU) run examples/disks_1e4.toml --out $(OUT)/disks_1e4
	$(MOREAU) evaluate-gaps $(MOCAP_DATA)/Qualisys.c3d --gap-seconds 0.1,0.2,0.5,1.0 \
	  --trials 20 --seed 1 --out $(OUT)/qualisys_evaluation
	$(MOREAU) fill-gaps $(MOCAP_DATA)/Vicon.c3d --out $(OUT)/vicon_filled
	PYTHONPATH=$(BUILD)/python $(PYTHON) examples/python/cell_colony.py $(OUT)/python_cell_colony
	$(MOREAU) run examples/abm/spheroid_3d.toml --out $(OUT)/spheroid
	$(PYTHON) scripts/plot_field.py $(OUT)/spheroid/fields.h5 --field oxygen --z 0 \
	  --trajectory $(OUT)/spheroid/trajectory.h5 --out $(OUT)/spheroid/oxygen.png
	$(MOREAU) run examples/abm/chemotaxis_2d.toml --out $(OUT)/chemotaxis
	$(PYTHON) scripts/plot_field.py $(OUT)/chemotaxis/fields.h5 --field signal \
	  --trajectory $(OUT)/chemotaxis/trajectory.h5 --out $(OUT)/chemotaxis/signal.png
	@echo "demo: figures are in $(OUT)/ (README.md says how to read them)"

# The agent-based examples' outputs that docs/abm.md quotes (docs/results/abm/) and their figures,
# about 30 s (docs/abm.md, "Where the numbers come from"; ABM_RESULTS_FLAGS=--long: the studies too).
abm-results: build
	./scripts/abm_results.sh $(MOREAU) $(ABM_RESULTS_FLAGS)

# The fields examples' outputs that docs/fields.md quotes (docs/results/fields/) and their figures:
# the 3D spheroid, its rim against the diffusion length, chemotactic aggregation (about 4 min).
fields-results: build
	./scripts/fields_results.sh $(MOREAU)

# Step sizes of the studies: h0 / 2^k.
SLIDING_H := 0.4,0.2,0.1,0.05,0.025,0.0125,0.00625,0.003125,0.0015625,0.00078125,0.000390625,0.0001953125,0.00009765625,0.000048828125,0.0000244140625
DISKS_H := 0.125,0.0625,0.03125,0.015625,0.0078125,0.00390625,0.001953125,0.0009765625,0.00048828125,0.000244140625,0.0001220703125,0.00006103515625,0.000030517578125

bench: build
	$(BUILD)/pbd_bench
	$(BUILD)/control_bench --benchmark_counters_tabular=true
	$(BUILD)/particles_bench --benchmark_repetitions=5 --benchmark_report_aggregates_only=true

format:
	@clang-format -i $$(git ls-files '*.h' '*.cpp')

clean:
	rm -rf build $(OUT)
