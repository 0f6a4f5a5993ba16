# Long random back-pressure runs of the control path (not part of make test).
.PHONY: soak
soak: setup ## Random stalls on every port, >= 10^6 cycles per configuration (nori 2 4 8 nodes x 2, 4, 64 ray IDs): every ray once, golden-exact -> build/soak/soak.json [SOAK_CYCLES= SOAK_SEED=]
	$(SBT) "runMain rtaccel.sim.Soak --cycles $(or $(SOAK_CYCLES),1000000)$(if $(SOAK_SEED), --seed $(SOAK_SEED))"
