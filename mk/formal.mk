# Formal checks of the control path (docs/formal.md). `make formal` and
# `make formal-deep` are part of `make test` (as formal-test, which runs the two
# side by side, one ABC process each): about 2 minutes on a 2-core machine
# (emission about 30 s, then n2 to depth 36 and n4 to depth 18), and about
# 40 s (PrepFetch alone to depth 17, LeafIntersect alone to depth 27);
# the mutants are not (they break the design on purpose), nor is formal-induction (pdr).
FORMAL_DIR := $(BUILD)/formal
.PHONY: formal formal-emit formal-mutants formal-deep formal-induction formal-test
test: formal-test

formal-test: setup formal-emit ## make formal and make formal-deep side by side (part of make test)
	scripts/formal.sh $(FORMAL_DIR) $(FORMAL_DEPTH) & core=$$!; \
	scripts/formal.sh $(FORMAL_DIR) "$(FORMAL_DEPTH)" cases-deep.txt; deep=$$?; \
	wait $$core; core=$$?; exit $$(( core || deep ))

formal-emit: setup-sbt
	$(SBT) "runMain rtaccel.formal.EmitFormal --out $(FORMAL_DIR)"

formal: setup formal-emit ## Bounded model check of the core's control path (part of make test)
	scripts/formal.sh $(FORMAL_DIR) $(FORMAL_DEPTH)

formal-mutants: formal ## Break the two-ID core on purpose; each break must be caught
	scripts/formal-mutants.sh $(FORMAL_DIR) $(or $(FORMAL_MUTANT_DEPTH),36)

formal-deep: setup formal-emit ## Per-unit bounded response by BMC past its bound (part of make test)
	scripts/formal.sh $(FORMAL_DIR) "$(FORMAL_DEPTH)" cases-deep.txt

formal-induction: setup formal-emit ## Not in make test: unbounded proofs (pdr, k-induction), time-limited
	scripts/formal-induction.sh $(FORMAL_DIR) $(or $(FORMAL_IND_SECS),300)

# The system top (docs/formal.md, "System level"): not in make test (Scala emission and Yosys alone take
# over a minute here). The core inside SystemCore is replaced by FormalCoreStub (read over RtAccel).
.PHONY: formal-system formal-system-emit formal-system-mutants formal-system-units
formal-system-emit: setup-sbt
	$(SBT) "runMain rtaccel.formal.EmitFormalSystem --out $(FORMAL_DIR)"

formal-system: setup formal-system-emit ## Not in make test: bounded model check of the system top
	scripts/formal.sh $(FORMAL_DIR) "$(FORMAL_DEPTH)" system-cases.txt

formal-system-mutants: setup formal-system-emit ## Not in make test: break the system top on purpose, each caught
	scripts/formal-system-mutants.sh $(FORMAL_DIR) $(or $(FORMAL_MUTANT_DEPTH),56)

formal-system-units: setup formal-system-emit ## Not in make test: RayDma, HitDma and ReadEngine proved alone
	scripts/formal-system-units.sh $(FORMAL_DIR) $(or $(FORMAL_IND_SECS),120) $(or $(FORMAL_BMC_SECS),600)
