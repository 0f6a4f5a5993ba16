# The register map's generated files, from its one source (RegisterMap.scala).
# PeakRDL (in a venv under build/) compiles the SystemRDL export to HTML, which
# also validates it.
REGMAP_VENV := $(BUILD)/venv-peakrdl

.PHONY: regmap
regmap: setup-sbt ## Regenerate the register map's C header, docs page and SystemRDL
	$(SBT) "runMain rtaccel.tools.RegMapGen"
	@if [ ! -x $(REGMAP_VENV)/bin/peakrdl ]; then \
	  python3 -m venv $(REGMAP_VENV) && $(REGMAP_VENV)/bin/pip install -q peakrdl peakrdl-html; fi
	$(REGMAP_VENV)/bin/peakrdl html docs/reports/rtaccel.rdl -o $(BUILD)/regmap/html
	@echo "regmap: SystemRDL export compiled by PeakRDL into $(BUILD)/regmap/html"
