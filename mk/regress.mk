# Accelerator speed measurements: writes docs/reports/performance.md.
# BVH_LAYOUTS: node layouts to compare (nori-bridge compile --bvh); MAX_RAYS:
# rays simulated per run, strided over the set;
# BENCH_RUNS: a subset of the runs (e.g. for a quick look);
# BOX_TEST=grid: the cores test child boxes in the node's grid (quantized
# layouts only: BVH_LAYOUTS=4q/8q, with BENCH_SYSTEM=0 or the system's BVH=4q).
# BVH=: the system section's cores read that layout (make verilog BVH= builds
# them); another system than the default (BVH=4, BOX_TEST=fp32) measures the
# per-core table in its layout only and writes its own page and caches:
# `make bench BVH=4q BOX_TEST=grid` -> docs/reports/performance-4q-grid.md.
BENCH_CONFIG = $(if $(filter-out 4,$(or $(BVH),4))$(filter-out fp32,$(BOX_TEST)),-$(or $(BVH),4)-$(or $(BOX_TEST),fp32))
BVH_LAYOUTS ?= $(if $(BENCH_CONFIG),$(BVH),nori 2 4 8)
BENCH_RUNS  ?= cornell-box-primary dragon-primary dragon-shadow dragon-ao monastery-primary monastery-shadow monastery-ao
BENCH_OUT   ?= docs/reports/performance$(BENCH_CONFIG).md
bench_list   = $(subst $(space),$(comma),$(strip $(1)))

# BENCH_SYSTEM=1 (default) adds the system section: the system top
# under the C++ harness for 1, 2, 4 and the cores that fit, the ZC706 estimate
# (cores that fit and the Fmax estimate read from build/verilog/resources.md,
# so `make verilog` runs first, cached per unit) beside Embree on this machine.
# BENCH_SYSTEM=cached redraws it from build/bench/system.json, re-reading
# resources.md (a later `make verilog` updates the estimate, and the page says
# which run each figure came from); BENCH_SYSTEM=embree (= make bench-embree)
# re-measures only Embree first, with the load average. Both redraw the
# per-core table from build/bench/bench.json too (BENCH_RENDER_ONLY=0 re-runs it).
BENCH_SYSTEM ?= 1
BENCH_RENDER_ONLY ?= $(if $(filter cached embree,$(BENCH_SYSTEM)),1,0)

.PHONY: bench bench-embree
bench: setup $(if $(filter monastery-%,$(BENCH_RUNS)),bridge-scenes-monastery) $(if $(filter 1,$(BENCH_SYSTEM)),verilog) ## Rays/cycle per layout and memory; ZC706 estimate vs Embree
	$(SBT) "runMain rtaccel.bench.Bench --out $(BENCH_OUT) --layouts $(call bench_list,$(BVH_LAYOUTS)) --runs $(call bench_list,$(BENCH_RUNS)) --max-rays $(or $(MAX_RAYS),2048) --system $(BENCH_SYSTEM) --render-only $(BENCH_RENDER_ONLY)$(if $(BOX_TEST), --box-test $(BOX_TEST)) --system-layout $(or $(BVH),4)$(if $(BENCH_CONFIG), --rows build/bench/bench$(BENCH_CONFIG).json --area build/bench/area$(BENCH_CONFIG).json)"

bench-embree: setup $(if $(filter monastery-%,$(BENCH_RUNS)),bridge-scenes-monastery) ## Re-measure only Embree and redraw docs/reports/performance.md
	$(MAKE) bench BENCH_SYSTEM=embree
