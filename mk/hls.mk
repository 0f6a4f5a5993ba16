# HLS twins of the intersection kernels (hls/) and their shared vector files.
# `make test-hls` (top-level Makefile) runs `make -C hls test`.
.PHONY: kernel-leaks hls-hard-cases hls-vectors

kernel-leaks: setup ## Regenerate docs/kernel-leaks.md: closed-mesh leak counts of the MT and watertight kernels (FP32)
	$(MAKE) -C hls leaks-doc

hls-hard-cases: setup ## Regenerate the committed hard-case vector files testdata/kernels/*.txt (deterministic)
	$(MAKE) -C hls hard-cases

hls-vectors: setup-apt ## Write hls/build/vectors/*.out (FP32 kernel outputs the Chisel tests compare against)
	$(MAKE) -C hls vectors
