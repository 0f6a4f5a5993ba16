# The C++ simulation of rtaccel_system and librtaccel (sw/, sw/README.md).
# cppsim-test runs in `make test`: the DDR/AXI model's unit test, the library
# built for the board backend, then librtaccel against the Verilated system on
# Cornell primary rays (16x16 = 256 rays), each hit compared with the golden
# model, and the library's error paths. Budget: under 4 minutes on 2 cores,
# the Verilator build of the one-core system included.
CPPSIM_PKG := $(BUILD)/cppsim/cornell-16x16
# The link cppsim-test points at its simulator build (rtaccel.regress.CppSim.TestSystemLink).
CPPSIM_TEST_SYSTEM := $(BUILD)/cppsim/test-system
CPPSIM_RAYS ?= 256

.PHONY: cppsim-test cppsim-lib
test: cppsim-test

cppsim-lib: setup-apt ## Build librtaccel (board backend) into build/cppsim/lib/
	$(MAKE) -C sw lib unit

$(CPPSIM_PKG)/image.bin: $(IMAGE_STAMP) | setup-cargo
	$(BRIDGE) compile scenes/cornell-box/cornell-box.xml --out $(CPPSIM_PKG) --rays primary --width 16 --height 16 --bvh 4 >/dev/null

cppsim-test: setup cppsim-lib $(CPPSIM_PKG)/image.bin ## librtaccel against the Verilated system top (part of make test)
	$(SBT) "runMain rtaccel.regress.CppSimTest --package $(CPPSIM_PKG) --out $(BUILD)/cppsim/test --rays $(CPPSIM_RAYS)"

# The two harnesses of the one-core system top side by side: the
# chiseltest one (SystemHarness + AxiMemoryModel) and the C++ one (rtaccel-sim:
# librtaccel + the C++ twin of AxiMemoryModel), same rays, same memory settings,
# same random draws. Fails unless every hit record and the batch's CYCLES agree;
# prints and writes (OUT/compare.json) both harnesses' simulated cycles per wall
# second and per CPU second (docs/cppsim.md). Not in make test: the chiseltest
# system build alone takes minutes.
CPPSIM_COMPARE_SCENE ?= scenes/cornell-box/cornell-box.xml
CPPSIM_COMPARE_RAYS_KIND ?= primary
# REORDER=0 (default): the exact check; with REORDER=1 the random draws fall in a different phase at START (docs/cppsim.md).
CPPSIM_COMPARE_PKG = $(BUILD)/cppsim/compare-pkg/$(basename $(notdir $(CPPSIM_COMPARE_SCENE)))-$(CPPSIM_COMPARE_RAYS_KIND)

.PHONY: cppsim-compare
cppsim-compare: setup ## The chiseltest and C++ system harnesses: same hits, same cycles
	$(BRIDGE) compile $(CPPSIM_COMPARE_SCENE) --out $(CPPSIM_COMPARE_PKG) --rays $(CPPSIM_COMPARE_RAYS_KIND) --bvh 4 >/dev/null
	$(SBT) "runMain rtaccel.regress.CppSimCompare --package $(CPPSIM_COMPARE_PKG) --out $(CPPSIM_COMPARE_PKG)-r$(or $(REORDER),0)$(if $(MAX_RAYS), --rays $(MAX_RAYS)) --reorder $(or $(REORDER),0)"

# The C++ harness's speed, measured to be trusted on a shared machine
# (docs/cppsim.md "Speed"): rtaccel-sim on the Cornell regression's rays (the
# 4,096 camera rays of `make regress SCENE=scenes/cornell-box/cornell-box.xml`,
# about 25k cycles) and on the dragon's 4,096 camera rays (about 62k cycles),
# CPPSIM_SPEED_RUNS times each, the builds alternating; every run's cycles per
# wall second and per CPU second and the load average, with medians, into
# build/cppsim/speed.json. A benchmark, not a test: nothing fails on speed.
# Uses the simulators that make regress SIM=cpp (clang; CPPSIM_CLANG=0 for the
# gcc one) and make cppsim-test (gcc) built; CPPSIM_SPEED_BUILDS= to choose
# (comma-separated).
CPPSIM_SPEED_RUNS ?= 5
# The one-core FP32 system: the build make cppsim-test links as test-system, and its clang twin.
CPPSIM_SYS1 = $(realpath $(CPPSIM_TEST_SYSTEM))
CPPSIM_SPEED_BUILDS ?= $(CPPSIM_SYS1)_clang,$(CPPSIM_SYS1)
CPPSIM_SPEED_PKGS := $(BUILD)/cppsim/speed/cornell-box-primary $(BUILD)/cppsim/speed/dragon-primary

# The timed packages, compiled once each (camera rays, 4-wide nodes).
$(BUILD)/cppsim/speed/%-primary/rays.csv: $(IMAGE_STAMP) | setup
	$(BRIDGE) compile scenes/$*/$*.xml --out $(@D) --rays primary --bvh 4 >/dev/null
$(BUILD)/cppsim/speed/dragon-primary/rays.csv: $(BRIDGE_CACHE)/dragon_res2.obj

.PHONY: cppsim-speed
cppsim-speed: setup $(addsuffix /rays.csv,$(CPPSIM_SPEED_PKGS)) ## Benchmark: the C++ harness's simulated cycles per second
	python3 sw/speed.py $(BUILD)/cppsim/speed.json $(CPPSIM_SPEED_RUNS) $(CPPSIM_SPEED_BUILDS) $(CPPSIM_SPEED_PKGS)

# The same builds' work per simulated cycle, independent of the machine's load
# (on this shared virtual machine even CPU seconds vary by +-30% from run to run;
# it has no hardware counters for perf stat): valgrind's cachegrind counts the
# instructions and simulates the branch predictor over the Cornell regression's
# rays (about 100 s per build under valgrind). A benchmark, prints only.
.PHONY: cppsim-instructions
cppsim-instructions: setup $(BUILD)/cppsim/speed/cornell-box-primary/rays.csv ## Benchmark: instructions per simulated cycle (valgrind cachegrind)
	@command -v valgrind >/dev/null || { SUDO=""; [ "$$(id -u)" = 0 ] || SUDO=sudo; \
	  $$SUDO apt-get update -qq && DEBIAN_FRONTEND=noninteractive $$SUDO apt-get install -y -qq valgrind >/dev/null; }
	@for b in $$(echo $(CPPSIM_SPEED_BUILDS) | tr , ' '); do \
	  o=$(BUILD)/cppsim/speed/cachegrind-$$(basename $$b); mkdir -p $$o; \
	  valgrind --tool=cachegrind --cache-sim=no --branch-sim=yes --cachegrind-out-file=$$o/cachegrind.out \
	    $$b/rtaccel-sim --package $(BUILD)/cppsim/speed/cornell-box-primary --out $$o \
	    --mem-latency 100-100 --fabric-mhz 200 --outstanding 64 --seed 1 >$$o/log.txt 2>&1 || { cat $$o/log.txt; exit 1; }; \
	  cyc=$$(python3 -c "import json;print(json.load(open('$$o/sim.json'))['simulatedCycles'])"); \
	  ir=$$(sed -n 's/.*I *refs: *\([0-9,]*\).*/\1/p' $$o/log.txt | tr -d ,); \
	  mp=$$(sed -n 's/.*Mispredicts: *\([0-9,]*\).*/\1/p' $$o/log.txt | tr -d ,); \
	  echo "cppsim-instructions: $$(basename $$b): $$cyc cycles, $$ir instructions ($$((ir / cyc)) per cycle), $$mp branch mispredictions ($$((mp / cyc)) per cycle)"; \
	done
