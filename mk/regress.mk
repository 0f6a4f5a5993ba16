# Accelerator speed measurements (issue 5): writes docs/performance.md.
.PHONY: bench
bench: setup ## Speed of the accelerator on Cornell box and dragon (camera/shadow/AO, latency 10 and 100, in-flight sweep) -> docs/performance.md
	$(SBT) "Test/runMain rtaccel.regress.Bench docs/performance.md"
