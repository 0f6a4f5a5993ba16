# Intersection datapaths: area and leak report. Tests run in `make test` (sbt test).
DATAPATH_AREA_JOBS ?= 2

.PHONY: datapath-area datapath-report datapath-test

datapath-area: setup-sbt ## Synthesise each datapath unit alone (Yosys; slow, resumable)
	$(SBT) "runMain rtaccel.report.DatapathArea $(BUILD)/datapath-area $(DATAPATH_AREA_JOBS)"

datapath-report: datapath-area ## Write docs/reports/datapath-report.md: latency, area, leaks
	$(SBT) "runMain rtaccel.report.DatapathReport $(BUILD)/datapath-area/area.tsv docs/reports/datapath-report.md"

datapath-test: setup-sbt hls-vectors ## Only the datapath specs
	$(SBT) "testOnly rtaccel.datapath.*"
