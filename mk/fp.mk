# Floating-point units (issue 3): area table. Tests run in `make test` (sbt test).
FP_AREA_JOBS ?= 2

.PHONY: fp-area fp-test

fp-area: setup ## Synthesise each FP unit (Yosys synth_xilinx xc7, several formats) into docs/fp-area.md; FP_AREA_JOBS=2
	$(SBT) "runMain rtaccel.report.FpAreaReport $(BUILD)/fp-area docs/fp-area.md $(FP_AREA_JOBS)"

fp-test: setup-sbt ## Run only the floating-point specs (golden model + Verilator unit runs)
	$(SBT) "testOnly rtaccel.fp.*"
