# Shaded images from the accelerator's hits, and nori-accel (golden walk,
# Nori drop-in). See docs/nori-dropin.md.
.PHONY: render nori-accel nori-accel-bench nori-accel-rtl-test
BRIDGE_BIN := nori-bridge/target/release/nori-bridge

# The C++ simulation of rtaccel_system in the configuration render and the
# drop-in use (ZC706, FP32 watertight conservative, 4-wide nodes), as make
# cppsim-test builds it: a link that cppsim-test points at its build
# (rtaccel.regress.CppSim.TestSystemLink). Rebuilt through cppsim-test when
# missing or older than the Chisel sources or sw/'s driver and harness.
NORI_SIMDIR := $(CPPSIM_TEST_SYSTEM)
$(NORI_SIMDIR)/rtaccel-sim: $(shell find src/main/scala -name '*.scala') $(wildcard sw/include/* sw/lib/* sw/sim/*)
	$(MAKE) cppsim-test
	touch $@

nori-accel: setup-apt ## Build nori-accel/: the golden walk and the Nori drop-in
	$(MAKE) -C nori-accel

render: setup nori-accel $(if $(filter 1,$(RTL)),$(NORI_SIMDIR)/rtaccel-sim) ## A shaded image from the accelerator's hits: SCENE=<scene.xml>
	RTL_SIMDIR=$(NORI_SIMDIR) scripts/render.sh

NORI_ACCEL_BENCH := build/nori-accel-bench
nori-accel-bench: setup nori-accel ## Golden-mode throughput of the Nori drop-in on 2 threads
	@mkdir -p $(NORI_ACCEL_BENCH)
	$(BRIDGE_BIN) compile scenes/cornell-box/cornell-box.xml --out $(NORI_ACCEL_BENCH)/cornell-primary --rays primary --width 256 --height 256 --bvh 4 >/dev/null
	$(BRIDGE_BIN) compile scenes/cornell-box/cornell-box.xml --out $(NORI_ACCEL_BENCH)/cornell-ao --rays ao --width 256 --height 256 --bvh 4 >/dev/null
	$(BRIDGE_BIN) compile scenes/dragon/dragon.xml --out $(NORI_ACCEL_BENCH)/dragon-ao --rays ao --width 128 --height 128 --bvh 4 >/dev/null
	@for p in cornell-primary cornell-ao dragon-ao; do nori-accel/build/dropin-check --bench $(NORI_ACCEL_BENCH)/$$p 2; done | tee $(NORI_ACCEL_BENCH)/bench.json
	@echo "nori-accel-bench: $(NORI_ACCEL_BENCH)/bench.json (wall-clock figures depend on the machine's load; mrays_per_cpu_s does not)"

# The drop-in's rtl mode (RTACCEL_MODE=rtl: librtaccel's simulation backend)
# against golden mode, hit for hit: from 4 threads on make cppsim-test's
# Cornell package (256 rays, every third a shadow ray, and 2 invalid rays),
# then from 2 threads on Cornell's 64x64 camera rays (4,096 rays), where the
# median batch must hold more than one ray (rays gathered across threads).
# RTACCEL_RTL_WINDOW_US=1000000: a batch closes as soon as every thread has a
# ray in it, so the long window costs nothing while the threads ask and keeps
# the batch-size check independent of the machine's load.
# Reuses cppsim-test's simulator build, so in make test it costs only the
# drop-in's link and the two runs.
NORI_RTL_PKG := $(BUILD)/nori-accel/cornell-64x64
$(NORI_RTL_PKG)/image.bin: $(IMAGE_STAMP) | setup-cargo
	$(BRIDGE_BIN) compile scenes/cornell-box/cornell-box.xml --out $(NORI_RTL_PKG) --rays primary --width 64 --height 64 --bvh 4 >/dev/null

test: nori-accel-rtl-test
nori-accel-rtl-test: setup nori-accel cppsim-test $(NORI_RTL_PKG)/image.bin ## The Nori drop-in's rtl mode (Verilated system via librtaccel) against golden mode, from 4 and 2 threads; batches gathered across threads (part of make test)
	$(MAKE) -C nori-accel rtl SIMDIR=$(abspath $(NORI_SIMDIR))
	RTACCEL_RTL_WINDOW_US=1000000 nori-accel/build/dropin-check-rtl --rtl $(CPPSIM_PKG) 256 4
	RTACCEL_RTL_WINDOW_US=1000000 nori-accel/build/dropin-check-rtl --rtl $(NORI_RTL_PKG) 4096 2
