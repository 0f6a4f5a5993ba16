# The C++ simulation of rtaccel_system and librtaccel (sw/, sw/README.md).
# cppsim-test runs in `make test`: the DDR/AXI model's unit test, the library
# built for the board backend, then librtaccel against the Verilated system on
# Cornell primary rays (16x16 = 256 rays), each hit compared with the golden
# model, and the library's error paths. Budget: under 4 minutes on 2 cores,
# the Verilator build of the one-core system included.
CPPSIM_PKG := $(BUILD)/cppsim/cornell-16x16
CPPSIM_RAYS ?= 256

.PHONY: cppsim-test cppsim-lib
test: cppsim-test

cppsim-lib: setup-apt ## librtaccel (board backend) into build/cppsim/lib/
	$(MAKE) -C sw lib unit

$(CPPSIM_PKG)/image.bin: | setup-cargo
	$(BRIDGE) compile scenes/cornell-box/cornell-box.xml --out $(CPPSIM_PKG) --rays primary --width 16 --height 16 --bvh 4 >/dev/null

cppsim-test: setup cppsim-lib $(CPPSIM_PKG)/image.bin ## librtaccel + the C++ Verilator harness on Cornell (part of make test)
	$(SBT) "Test/runMain rtaccel.regress.CppSimTest --package $(CPPSIM_PKG) --out $(BUILD)/cppsim/test --rays $(CPPSIM_RAYS)"

# The two harnesses of the one-core system top side by side (issue 13): the
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
cppsim-compare: setup ## The chiseltest and C++ system harnesses on the same rays: same hits and cycles, and their speed [CPPSIM_COMPARE_SCENE= CPPSIM_COMPARE_RAYS_KIND=primary|shadow|ao MAX_RAYS= REORDER=0|1]
	$(BRIDGE) compile $(CPPSIM_COMPARE_SCENE) --out $(CPPSIM_COMPARE_PKG) --rays $(CPPSIM_COMPARE_RAYS_KIND) --bvh 4 >/dev/null
	$(SBT) "Test/runMain rtaccel.regress.CppSimCompare --package $(CPPSIM_COMPARE_PKG) --out $(CPPSIM_COMPARE_PKG)-r$(or $(REORDER),0)$(if $(MAX_RAYS), --rays $(MAX_RAYS)) --reorder $(or $(REORDER),0)"
