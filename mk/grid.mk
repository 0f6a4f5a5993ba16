# The grid box test of quantized nodes (docs/kernels.md, "Box tests in the node's grid").

.PHONY: grid-area grid-test

grid-area: setup ## Yosys area and longest path of the grid box test (one lane, the per-node stage, the 4-wide unit) into build/grid/area.md
	$(SBT) "runMain rtaccel.tools.GridArea $(BUILD)/grid/area.md"

grid-test: setup-sbt ## Only the grid box test's spec (exhaustive e3m3 axis, random FP32 against the exact test, RTL against golden)
	$(SBT) "testOnly rtaccel.traversal.GridBboxIntersectSpec"
