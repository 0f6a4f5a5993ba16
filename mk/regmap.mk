# The register map's generated files, from its one source (RegisterMap.scala).
# PeakRDL (in a venv under build/) compiles the SystemRDL export to HTML, which
# also validates it.
REGMAP_VENV := $(BUILD)/venv-peakrdl

.PHONY: regmap
regmap: setup-sbt ## Regenerate sw/include/rtaccel_regs.h, docs/register-map.md, docs/rtaccel.rdl; PeakRDL HTML into build/regmap/html
	$(SBT) "runMain rtaccel.tools.RegMapGen"
	@if [ ! -x $(REGMAP_VENV)/bin/peakrdl ]; then \
	  python3 -m venv $(REGMAP_VENV) && $(REGMAP_VENV)/bin/pip install -q peakrdl peakrdl-html; fi
	$(REGMAP_VENV)/bin/peakrdl html docs/rtaccel.rdl -o $(BUILD)/regmap/html
	@echo "regmap: SystemRDL export compiled by PeakRDL into $(BUILD)/regmap/html"
