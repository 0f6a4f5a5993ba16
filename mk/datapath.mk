# Intersection datapaths (issue 4): area and leak report. Tests run in `make test` (sbt test).
DATAPATH_AREA_JOBS ?= 2

.PHONY: datapath-area datapath-report datapath-test

datapath-area: setup-sbt ## Synthesise each datapath unit alone (Yosys synth_xilinx xc7; slow, resumable) into $(BUILD)/datapath-area/area.tsv
	$(SBT) "runMain rtaccel.report.DatapathArea $(BUILD)/datapath-area $(DATAPATH_AREA_JOBS)"

datapath-report: datapath-area ## Write docs/datapath-report.md: latencies, xc7 area beside the seed's HLS, leak counts per variant and format
	$(SBT) "runMain rtaccel.report.DatapathReport $(BUILD)/datapath-area/area.tsv docs/datapath-report.md"

datapath-test: setup-sbt hls-vectors ## Run only the datapath specs (golden vs HLS vectors, Verilator units, leaks, properties)
	$(SBT) "testOnly rtaccel.datapath.*"
