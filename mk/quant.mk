# Quantized child boxes: the bench's table for the FP32
# wide layouts beside their quantized twins, Cornell and dragon camera rays,
# on chip and under the ZC706 DDR model -> docs/reports/quant-performance.md. No system
# section (`make bench`'s), and its own rows (build/bench/quant.json), so it never
# overwrites make bench's; a hand-written reading would be docs/reports/quant-performance-notes.md.
QUANT_LAYOUTS ?= 4 4q 8 8q
QUANT_RUNS    ?= cornell-box-primary dragon-primary

.PHONY: bench-quant
bench-quant: setup ## Node bytes per ray and rays/cycle, 4 vs 4q and 8 vs 8q
	$(SBT) "runMain rtaccel.bench.Bench --out docs/reports/quant-performance.md --area build/bench/area-quant.json --layouts $(call bench_list,$(QUANT_LAYOUTS)) --runs $(call bench_list,$(QUANT_RUNS)) --max-rays $(or $(MAX_RAYS),2048) --system 0 --rows build/bench/quant.json"
