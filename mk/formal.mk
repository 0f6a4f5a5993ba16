# Formal checks of the control path (docs/formal.md). `make formal` is part of
# `make test`: about 3 minutes on an idle 2-core machine (emission 40 s, n2 38 s,
# n4 107 s); the mutants are not (they break the design on purpose).
FORMAL_DIR := $(BUILD)/formal
.PHONY: formal formal-emit formal-mutants
test: formal

formal-emit: setup-sbt
	$(SBT) "Test/runMain rtaccel.formal.EmitFormal --out $(FORMAL_DIR)"

formal: setup formal-emit ## Bounded model check of small RtAccel configurations (Yosys -> AIGER -> ABC bmc3): no overflow, IDs once, every ray once -> build/formal/formal.log [FORMAL_DEPTH=]
	scripts/formal.sh $(FORMAL_DIR) $(FORMAL_DEPTH)

formal-mutants: formal ## Break the n2 design on purpose three ways (each must be caught) and two probes (leaf round trip inside the depth; bounded_response can fail) -> build/formal/mutants.log [FORMAL_MUTANT_DEPTH=28]
	scripts/formal-mutants.sh $(FORMAL_DIR) $(or $(FORMAL_MUTANT_DEPTH),28)
