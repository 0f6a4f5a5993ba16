# Speed against error (issue 6): `make speed-vs-error` regenerates
# docs/speed-vs-error.{md,json} and its plots from nothing. Every point is an
# independent job with one command line (java ... SweepPoint / PointArea), so
# `make -j` spreads them over cores and a batch scheduler over machines.
SWEEP          ?= $(BUILD)/sweep
SWEEP_JOBS     ?= 2
SWEEP_FORMATS  ?= e8m23 e8m19 e8m18 e8m15 e8m12 e8m10 e8m7 e6m9
SWEEP_ROUNDING ?= rne cons
SWEEP_TESTS    ?= mt wt
SWEEP_POINTS   := $(foreach f,$(SWEEP_FORMATS),$(foreach r,$(SWEEP_ROUNDING),$(foreach t,$(SWEEP_TESTS),$(f)-$(r)-$(t))))
HARD_CASES     := $(patsubst scenes/hard/%/expect.csv,%,$(wildcard scenes/hard/*/expect.csv))
# Image runs: the Cornell box and the ~200k-triangle dragon, camera and AO rays.
IMAGE_RUNS     := cornell-box-primary cornell-box-ao dragon-primary dragon-ao
SWEEP_RUNS     := $(IMAGE_RUNS) $(addprefix hard-,$(HARD_CASES))
SPEED_RAYS     ?= 1024
# local: make -j$(SWEEP_JOBS) on this machine; slurm: one Slurm job array
# (scripts/slurm/sweep-array.sh); `make slurm-up` starts a one-node cluster.
SWEEP_ENGINE   ?= local
SWEEP_JAVA     := java -Xss8m -Xmx3g -cp "$$(cat $(SWEEP)/classpath)"
comma := ,
empty :=
space := $(empty) $(empty)

.PHONY: speed-vs-error sweep-jobs sweep-packages sweep-clean

speed-vs-error: setup ## Precision sweep (formats x rounding x triangle test x scenes): docs/speed-vs-error.{md,json} + plots [SWEEP_JOBS=2 SWEEP_FORMATS=... SWEEP_ENGINE=local|slurm]
	@start=$$(date +%s); \
	rm -f $(SWEEP)/classpath && $(MAKE) --no-print-directory $(SWEEP)/classpath && \
	$(MAKE) --no-print-directory sweep-run-$(SWEEP_ENGINE) && \
	end=$$(date +%s); \
	$(BRIDGE) sweep-report --sweep $(SWEEP) --json docs/speed-vs-error.json --md docs/speed-vs-error.md --plots docs/speed-vs-error \
	  --runtime-note "$(words $(SWEEP_POINTS)) points; the last make speed-vs-error took $$(( (end - start + 30) / 60 )) min wall with $(if $(filter slurm,$(SWEEP_ENGINE)),a Slurm job array,make -j$(SWEEP_JOBS)) on $$(nproc) cores on $$(date -u +%Y-%m-%d) (jobs already done are not rerun)"

# The point jobs: what `make -j` runs here, or what a Slurm array runs.
SWEEP_POINT_JOBS := $(addprefix $(SWEEP)/points/,$(addsuffix .json,$(SWEEP_POINTS))) \
            $(if $(HARD_CASES),$(addprefix $(SWEEP)/points/,$(addsuffix .hard.json,$(SWEEP_POINTS)))) \
            $(addprefix $(SWEEP)/area/,$(addsuffix .json,$(SWEEP_POINTS)))
# Their shared inputs, built once before the jobs (two array tasks must never
# race to build the same package).
SWEEP_SHARED := $(SWEEP)/classpath $(foreach r,$(SWEEP_RUNS),$(SWEEP)/packages/$(r)/package.json) \
            $(foreach c,$(HARD_CASES),$(foreach r,embree robust double,$(SWEEP)/hard-ref/$(c)-$(r).json))

.PHONY: sweep-run-local sweep-run-slurm
sweep-run-local:
	$(MAKE) --no-print-directory -j$(SWEEP_JOBS) sweep-jobs
sweep-run-slurm:
	$(MAKE) --no-print-directory -j$(SWEEP_JOBS) $(SWEEP_SHARED)
	scripts/slurm/sweep-array.sh $(SWEEP) SWEEP=$(SWEEP) SPEED_RAYS=$(SPEED_RAYS) -- $(SWEEP_POINT_JOBS)

sweep-jobs: $(addprefix $(SWEEP)/points/,$(addsuffix .json,$(SWEEP_POINTS))) \
            $(if $(HARD_CASES),$(addprefix $(SWEEP)/points/,$(addsuffix .hard.json,$(SWEEP_POINTS)))) \
            $(addprefix $(SWEEP)/area/,$(addsuffix .json,$(SWEEP_POINTS))) \
            $(foreach c,$(HARD_CASES),$(foreach r,embree robust double,$(SWEEP)/hard-ref/$(c)-$(r).json))

# Compiled once, before the parallel jobs: each job is then a plain `java` command.
# Jobs depend on it and on the (deterministic) packages order-only: `make
# speed-vs-error` refreshes the classpath, and a rerun after an interruption
# redoes only the missing points (`make sweep-clean` to redo everything, e.g.
# after changing a scene or the hardware).
$(SWEEP)/classpath:
	@mkdir -p $(SWEEP)
	$(SBT) "Test/compile" "export Test/fullClasspath" | tail -1 > $(SWEEP)/classpath.tmp
	@grep -q 'test-classes' $(SWEEP)/classpath.tmp || { echo "sweep: sbt did not print the classpath"; exit 1; }
	@mv $(SWEEP)/classpath.tmp $(SWEEP)/classpath

sweep-packages: $(foreach r,$(SWEEP_RUNS),$(SWEEP)/packages/$(r)/package.json)

$(SWEEP)/packages/cornell-box-primary/package.json: scenes/cornell-box/cornell-box.xml
	$(BRIDGE) compile $< --out $(@D) --rays primary --width 96 --height 96
$(SWEEP)/packages/cornell-box-ao/package.json: scenes/cornell-box/cornell-box.xml
	$(BRIDGE) compile $< --out $(@D) --rays ao --width 64 --height 64 --spp 2
$(SWEEP)/packages/dragon-primary/package.json: scenes/dragon/dragon.xml
	$(BRIDGE) compile $< --out $(@D) --rays primary --width 128 --height 128
$(SWEEP)/packages/dragon-ao/package.json: scenes/dragon/dragon.xml
	$(BRIDGE) compile $< --out $(@D) --rays ao --width 128 --height 128 --spp 2
# Hard cases: the sweep's package holds the f64 reference; two more hold Embree's answers without and with ROBUST.
$(SWEEP)/packages/hard-%/package.json: scenes/hard/%/expect.csv
	$(BRIDGE) compile scenes/hard/$*/$*.xml --out $(@D) --rays scenes/hard/$*/rays.txt --reference double
$(SWEEP)/hard-pkg/%-embree/package.json: scenes/hard/%/expect.csv
	$(BRIDGE) compile scenes/hard/$*/$*.xml --out $(@D) --rays scenes/hard/$*/rays.txt --reference embree
$(SWEEP)/hard-pkg/%-robust/package.json: scenes/hard/%/expect.csv
	$(BRIDGE) compile scenes/hard/$*/$*.xml --out $(@D) --rays scenes/hard/$*/rays.txt --reference embree --robust

$(SWEEP)/hard-ref/%-double.json: $(SWEEP)/packages/hard-%/package.json
	@mkdir -p $(@D)
	$(BRIDGE) hard-score --package $(<D) --hits $(<D)/reference.csv --expect scenes/hard/$*/expect.csv --out $@
$(SWEEP)/hard-ref/%-embree.json: $(SWEEP)/hard-pkg/%-embree/package.json
	@mkdir -p $(@D)
	$(BRIDGE) hard-score --package $(<D) --hits $(<D)/reference.csv --expect scenes/hard/$*/expect.csv --out $@
$(SWEEP)/hard-ref/%-robust.json: $(SWEEP)/hard-pkg/%-robust/package.json
	@mkdir -p $(@D)
	$(BRIDGE) hard-score --package $(<D) --hits $(<D)/reference.csv --expect scenes/hard/$*/expect.csv --out $@

# The references alone, plus nori-bridge's f32 software trace (the hardware's
# algorithm in f32), on every hard case.
.PHONY: hard-measure
hard-measure: setup-cargo ## Score Embree (plain, ROBUST), the f64 reference and the f32 software trace on every hard case -> $(SWEEP)/hard-ref/*.json
	@$(MAKE) --no-print-directory $(foreach c,$(HARD_CASES),$(foreach r,embree robust double trace,$(SWEEP)/hard-ref/$(c)-$(r).json))
$(SWEEP)/hard-ref/%-trace.json: $(SWEEP)/packages/hard-%/package.json
	@mkdir -p $(@D)
	$(BRIDGE) trace --package $(<D) --out $(@D)/$*-trace.csv
	$(BRIDGE) hard-score --package $(<D) --hits $(@D)/$*-trace.csv --expect scenes/hard/$*/expect.csv --out $@

# One point: $* = <format>-<rne|cons>-<mt|wt>. Two jobs per point: the image
# runs (error on every ray, speed in RTL) and the hard cases (error only);
# sweep-report merges `<point>.hard.json` into `<point>.json`.
sweep_field = $(word $(1),$(subst -, ,$(2)))
sweep_point_args = --float $(call sweep_field,1,$(1)) --rounding $(call sweep_field,2,$(1)) --triangle $(call sweep_field,3,$(1)) --sweep $(SWEEP)
$(SWEEP)/points/%.hard.json: | $(foreach c,$(HARD_CASES),$(SWEEP)/packages/hard-$(c)/package.json) $(SWEEP)/classpath
	@mkdir -p $(SWEEP)/logs
	$(SWEEP_JAVA) rtaccel.sweep.SweepPoint $(call sweep_point_args,$*) --group hard \
	  --runs $(subst $(space),$(comma),$(addprefix hard-,$(HARD_CASES))) > $(SWEEP)/logs/point-$*.hard.log 2>&1 \
	  || { tail -30 $(SWEEP)/logs/point-$*.hard.log; exit 1; }
	@tail -1 $(SWEEP)/logs/point-$*.hard.log
$(SWEEP)/points/%.json: | $(foreach r,$(IMAGE_RUNS),$(SWEEP)/packages/$(r)/package.json) $(SWEEP)/classpath
	@mkdir -p $(SWEEP)/logs
	$(SWEEP_JAVA) rtaccel.sweep.SweepPoint $(call sweep_point_args,$*) --runs $(subst $(space),$(comma),$(IMAGE_RUNS)) \
	  --speed-runs $(subst $(space),$(comma),$(IMAGE_RUNS)) --speed-rays $(SPEED_RAYS) > $(SWEEP)/logs/point-$*.log 2>&1 \
	  || { tail -30 $(SWEEP)/logs/point-$*.log; exit 1; }
	@tail -1 $(SWEEP)/logs/point-$*.log
$(SWEEP)/area/%.json: | $(SWEEP)/classpath
	@mkdir -p $(SWEEP)/logs
	$(SWEEP_JAVA) rtaccel.tools.PointArea --float $(call sweep_field,1,$*) --rounding $(call sweep_field,2,$*) \
	  --triangle $(call sweep_field,3,$*) --out $@ > $(SWEEP)/logs/area-$*.log 2>&1 || { tail -30 $(SWEEP)/logs/area-$*.log; exit 1; }
	@tail -1 $(SWEEP)/logs/area-$*.log

sweep-clean: ## Remove the sweep's outputs (not the shared Yosys cache build/area-cache)
	rm -rf $(SWEEP)
