# System-level measurement: rays/cycle of RtAccelSystem with N cores
# under the AXI DDR model; rows go to build/bench/system.md.
SYSTEM_BENCH_SCENE ?= scenes/cornell-box/cornell-box.xml

.PHONY: system-bench
system-bench: setup ## Rays/cycle of the system top for CORES=1 2 4 (chiseltest)
	$(BRIDGE) compile $(SYSTEM_BENCH_SCENE) --out $(BUILD)/bench/system-pkg --rays primary --bvh 4
	for n in $(or $(CORES),1 2 4); do \
	  $(SBT) "runMain rtaccel.bench.SystemBench --package $(BUILD)/bench/system-pkg --cores $$n$(if $(RAYS), --rays $(RAYS))"; done
