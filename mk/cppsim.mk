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
