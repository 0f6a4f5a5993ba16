# HLS twins of the intersection kernels (hls/) and their shared vector files.
# `make test-hls` (top-level Makefile) runs `make -C hls test`.
.PHONY: kernel-leaks hls-hard-cases hls-vectors

kernel-leaks: setup ## Closed-mesh leak counts of the C++ kernels -> docs/reports/
	$(MAKE) -C hls leaks-doc

hls-hard-cases: setup ## Regenerate testdata/kernels/*.txt (deterministic)
	$(MAKE) -C hls hard-cases

hls-vectors: setup-apt ## Write hls/build/vectors/*.out for the Chisel specs
	$(MAKE) -C hls vectors
