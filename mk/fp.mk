# Floating-point units: area table. Tests run in `make test` (sbt test).
FP_AREA_JOBS ?= 2

.PHONY: fp-area fp-test recip-area

fp-area: setup ## Synthesise each FP unit in several formats -> docs/reports/fp-area.md
	$(SBT) "runMain rtaccel.report.FpAreaReport $(BUILD)/fp-area docs/reports/fp-area.md $(FP_AREA_JOBS)"

fp-test: setup-sbt ## Only the floating-point specs
	$(SBT) "testOnly rtaccel.fp.*"

recip-area: setup ## Yosys area and longest path of the ray setup and its reciprocal units into build/recip/area.md
	$(SBT) "runMain rtaccel.tools.RecipArea $(BUILD)/recip/area.md"
