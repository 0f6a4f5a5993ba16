# Formal checks of the control path (docs/formal.md). `make formal` is part of
# `make test`: about 3 minutes on an idle 2-core machine in session 5 (emission 40 s, n2 38 s,
# n4 107 s; n4 is now cut to depth 18 to pay for ray_conservation); the mutants are not (they break the design on purpose), nor are
# formal-deep (per-unit bounded response by BMC) and formal-induction (pdr).
FORMAL_DIR := $(BUILD)/formal
.PHONY: formal formal-emit formal-mutants formal-deep formal-induction
test: formal

formal-emit: setup-sbt
	$(SBT) "runMain rtaccel.formal.EmitFormal --out $(FORMAL_DIR)"

formal: setup formal-emit ## Bounded model check of small RtAccel configurations (Yosys -> AIGER -> ABC bmc3): no overflow, IDs once, every ray once -> build/formal/formal.log [FORMAL_DEPTH=]
	scripts/formal.sh $(FORMAL_DIR) $(FORMAL_DEPTH)

formal-mutants: formal ## Break the n2 design on purpose three ways (each must be caught) and two probes (leaf round trip inside the depth; bounded_response can fail) -> build/formal/mutants.log [FORMAL_MUTANT_DEPTH=28]
	scripts/formal-mutants.sh $(FORMAL_DIR) $(or $(FORMAL_MUTANT_DEPTH),28)

formal-deep: setup formal-emit ## Not in make test: per-unit bounded response by BMC past the derived bound (PrepFetch fetch2, LeafIntersect leaf2f; about 1 min) -> build/formal/formal-cases-deep.log [FORMAL_DEPTH=]
	scripts/formal.sh $(FORMAL_DIR) "$(FORMAL_DEPTH)" cases-deep.txt

formal-induction: setup formal-emit ## Unbounded proofs, not in make test: by pdr RayIdFreeList's properties and PrepFetch's and LeafIntersect's bounded response; the n2 core's safety by k-induction and pdr, time-limited -> build/formal/formal-induction.log [FORMAL_IND_SECS=300]
	scripts/formal-induction.sh $(FORMAL_DIR) $(or $(FORMAL_IND_SECS),300)

# The system top (docs/formal.md, "System level"): not in make test (Scala emission and Yosys alone take
# over a minute here). The core inside SystemCore is replaced by FormalCoreStub (read over RtAccel).
.PHONY: formal-system formal-system-emit formal-system-mutants formal-system-units
formal-system-emit: setup-sbt
	$(SBT) "runMain rtaccel.formal.EmitFormalSystem --out $(FORMAL_DIR)"

formal-system: setup formal-system-emit ## Not in make test: bounded model check of SystemCore (1 core as an abstract stub, AXI slave and host as assumptions): no overflow, each ray read once, each hit written once inside the hit buffer, DONE after all -> build/formal/formal-system-cases.log [FORMAL_DEPTH=]
	scripts/formal.sh $(FORMAL_DIR) "$(FORMAL_DEPTH)" system-cases.txt

formal-system-mutants: setup formal-system-emit ## Not in make test: break the system design and its units on purpose (each break must be caught) and probes of what the depth reaches -> build/formal/system-mutants.log [FORMAL_MUTANT_DEPTH=40]
	scripts/formal-system-mutants.sh $(FORMAL_DIR) $(or $(FORMAL_MUTANT_DEPTH),40)

formal-system-units: setup formal-system-emit ## Not in make test: RayDma, HitDma and ReadEngine alone (BMC past each derived bound where it reaches, then pdr) -> build/formal/formal-system-units.log [FORMAL_IND_SECS=120]
	scripts/formal-system-units.sh $(FORMAL_DIR) $(or $(FORMAL_IND_SECS),120)
