# Formal checks of the control path (docs/formal.md). `make formal` is part of
# `make test`: about 3 minutes on an idle 2-core machine in session 5 (emission 40 s, n2 38 s,
# n4 107 s; n4 is now cut to depth 18 to pay for ray_conservation); the mutants are not (they break the design on purpose), nor are
# formal-deep (per-unit bounded response by BMC) and formal-induction (pdr).
FORMAL_DIR := $(BUILD)/formal
.PHONY: formal formal-emit formal-mutants formal-deep formal-induction
test: formal

formal-emit: setup-sbt
	$(SBT) "Test/runMain rtaccel.formal.EmitFormal --out $(FORMAL_DIR)"

formal: setup formal-emit ## Bounded model check of small RtAccel configurations (Yosys -> AIGER -> ABC bmc3): no overflow, IDs once, every ray once -> build/formal/formal.log [FORMAL_DEPTH=]
	scripts/formal.sh $(FORMAL_DIR) $(FORMAL_DEPTH)

formal-mutants: formal ## Break the n2 design on purpose three ways (each must be caught) and two probes (leaf round trip inside the depth; bounded_response can fail) -> build/formal/mutants.log [FORMAL_MUTANT_DEPTH=28]
	scripts/formal-mutants.sh $(FORMAL_DIR) $(or $(FORMAL_MUTANT_DEPTH),28)

formal-deep: setup formal-emit ## Not in make test: per-unit bounded response by BMC past the derived bound (PrepFetch fetch2, LeafIntersect leaf2f; about 1 min) -> build/formal/formal-cases-deep.log [FORMAL_DEPTH=]
	scripts/formal.sh $(FORMAL_DIR) "$(FORMAL_DEPTH)" cases-deep.txt

formal-induction: setup formal-emit ## Unbounded proofs, not in make test: by pdr RayIdFreeList's properties and PrepFetch's and LeafIntersect's bounded response; the n2 core's safety by k-induction and pdr, time-limited -> build/formal/formal-induction.log [FORMAL_IND_SECS=300]
	scripts/formal-induction.sh $(FORMAL_DIR) $(or $(FORMAL_IND_SECS),300)
