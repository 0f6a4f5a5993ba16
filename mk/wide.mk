# The m_axi width (docs/system-wide.md): every SystemConfig that names no
# width takes AXI_DATA_BITS (512 by default, or 1024) from the environment, so
# `make verilog AXI_DATA_BITS=1024`, `make cppsim-test AXI_DATA_BITS=1024` and the
# system specs under it build the wide system. bench-wide measures the system's
# rays/cycle for each width and core count (not in make test).
WIDE_WIDTHS ?= 512 1024
WIDE_CORES ?= 1 2 4
WIDE_MHZ ?= 100

.PHONY: bench-wide
bench-wide: setup ## Benchmark: system rays/cycle for m_axi 512 vs 1024 bits, 1 to 4 cores
	$(SBT) "runMain rtaccel.bench.BenchWide --widths $(call bench_list,$(WIDE_WIDTHS)) --cores $(call bench_list,$(WIDE_CORES)) --mhz $(WIDE_MHZ) --max-rays $(or $(MAX_RAYS),2048)"
