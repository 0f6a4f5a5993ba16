# Formal checks of the control path (docs/formal.md). Not part of `make test`:
# on the shared 2-core machine they take longer than the budget allows.
FORMAL_DIR := $(BUILD)/formal
.PHONY: formal formal-emit formal-mutants

formal-emit: setup-sbt
	$(SBT) "Test/runMain rtaccel.formal.EmitFormal --out $(FORMAL_DIR)"

formal: setup formal-emit ## Bounded model check of small RtAccel configurations (Yosys SAT): no overflow, IDs once, every ray once -> build/formal/formal.log [FORMAL_DEPTH=]
	scripts/formal.sh $(FORMAL_DIR) $(FORMAL_DEPTH)

formal-mutants: formal ## Break the n2 design on purpose three ways; each must be caught -> build/formal/mutants.log [FORMAL_MUTANT_DEPTH=16]
	scripts/formal-mutants.sh $(FORMAL_DIR) $(or $(FORMAL_MUTANT_DEPTH),16)
