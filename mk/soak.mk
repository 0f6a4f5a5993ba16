# Long random back-pressure runs of the control path (not part of make test).
.PHONY: soak
soak: setup ## Random stalls on every port, >= 10^6 cycles per configuration
	$(SBT) "runMain rtaccel.sim.Soak --cycles $(or $(SOAK_CYCLES),1000000)$(if $(SOAK_SEED), --seed $(SOAK_SEED))"
