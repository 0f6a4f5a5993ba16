# Accelerator speed measurements: writes docs/performance.md.
# BVH_LAYOUTS: node layouts to compare (nori-bridge compile --bvh); MAX_RAYS:
# rays simulated per run, strided over the set;
# BENCH_RUNS: a subset of the runs (e.g. for a quick look).
BVH_LAYOUTS ?= nori 2 4 8
BENCH_RUNS  ?= cornell-box-primary dragon-primary dragon-shadow dragon-ao
BENCH_OUT   ?= docs/performance.md
bench_list   = $(subst $(space),$(comma),$(strip $(1)))

.PHONY: bench
bench: setup ## Speed side by side: BVH layouts x memory (onchip, ddr) x Cornell/dragon rays -> docs/performance.md [BVH_LAYOUTS="nori 2 4 8" MAX_RAYS=2048 BENCH_RUNS=]
	$(SBT) "Test/runMain rtaccel.regress.Bench --out $(BENCH_OUT) --layouts $(call bench_list,$(BVH_LAYOUTS)) --runs $(call bench_list,$(BENCH_RUNS)) --max-rays $(or $(MAX_RAYS),2048)"
