# make faults (docs/faults.md): faults injected into the C++ simulation of the
# board (SLVERR/DECERR on each kind of read and on hit writes, responses that
# never come, the scene overwritten mid-batch, ABORT at random cycles, a lost
# interrupt) and librtaccel's recovery from each, then librtaccel under bad
# use. Prints the table and writes it to docs/reports/faults.md. Runs on
# make cppsim-test's package and simulator build (reused if built). Not in make
# test: a few minutes of simulation.
FAULTS_TRIALS ?= 10
FAULTS_SEED ?= 1

.PHONY: faults
faults: setup $(CPPSIM_PKG)/image.bin ## Fault injection and recovery on the C++ board simulation; table into docs/reports/faults.md [FAULTS_TRIALS=10 FAULTS_SEED=1]
	$(SBT) "runMain rtaccel.regress.CppSimFaults --package $(CPPSIM_PKG) --out $(BUILD)/faults --rays $(CPPSIM_RAYS) --trials $(FAULTS_TRIALS) --seed $(FAULTS_SEED) --report docs/reports/faults.md"
