# Speed against error: `make speed-vs-error` regenerates
# docs/reports/speed-vs-error.{md,json} and its plots from nothing. Every point is an
# independent job with one command line (java ... SweepPoint / PointArea), so
# `make -j` spreads them over cores and a batch scheduler over machines.
SWEEP          ?= $(BUILD)/sweep
SWEEP_JOBS     ?= 2
# The grid: layout x box format x triangle format x box rounding x
# triangle test. A point is `<layout>-<box>-<tri>-<rne|cons>-<mt|wt>`, e.g.
# 4q-e8m10-e8m23-cons-wt, and `-grid` after it tests a 4q/8q node's children in
# the node's grid (BOX_TEST=grid; FP32 box constants). SWEEP_GRID=full runs every combination of the
# SWEEP_* lists below; SWEEP_GRID=reduced (the default) the SWEEP_REDUCED
# points; SWEEP_POINTS="..." names points directly.
SWEEP_LAYOUTS     ?= 4 8 4q 8q
SWEEP_BOX_FORMATS ?= e8m23 e8m15 e8m12 e8m10 e6m9
SWEEP_TRI_FORMATS ?= e8m23 e8m18 e8m15
SWEEP_ROUNDING    ?= rne cons
SWEEP_TESTS       ?= mt wt
SWEEP_FULL     := $(foreach l,$(SWEEP_LAYOUTS),$(foreach b,$(SWEEP_BOX_FORMATS),$(foreach t,$(SWEEP_TRI_FORMATS),$(foreach r,$(SWEEP_ROUNDING),$(foreach x,$(SWEEP_TESTS),$(l)-$(b)-$(t)-$(r)-$(x))))))
# FP32 baselines for K = 4 and 8; 4q/8q with FP32 boxes; 4q/8q with narrow
# conservative boxes and FP32 watertight triangles; two narrowed-triangle points;
# the 4q grid box test.
SWEEP_REDUCED  ?= 4-e8m23-e8m23-cons-wt 8-e8m23-e8m23-cons-wt 4q-e8m23-e8m23-cons-wt 8q-e8m23-e8m23-cons-wt \
                  4q-e8m12-e8m23-cons-wt 4q-e8m10-e8m23-cons-wt 4q-e6m9-e8m23-cons-wt \
                  8q-e8m12-e8m23-cons-wt 8q-e8m10-e8m23-cons-wt 8q-e6m9-e8m23-cons-wt \
                  4q-e8m10-e8m18-cons-wt 4q-e8m10-e8m15-cons-wt 4q-e8m23-e8m23-cons-wt-grid
SWEEP_GRID     ?= reduced
SWEEP_POINTS   ?= $(if $(filter full,$(SWEEP_GRID)),$(SWEEP_FULL),$(SWEEP_REDUCED))
sweep_field = $(word $(1),$(subst -, ,$(2)))
SWEEP_USED_LAYOUTS = $(sort $(foreach p,$(SWEEP_POINTS),$(call sweep_field,1,$(p))))
# The layout whose hard-case packages hold the references (layout-independent).
SWEEP_REF_LAYOUT := 4
HARD_CASES     := $(patsubst scenes/hard/%/expect.csv,%,$(wildcard scenes/hard/*/expect.csv))
# Image runs: the Cornell box and the ~200k-triangle dragon, camera and AO rays
# (sizes: SWEEP_CORNELL_PX, SWEEP_DRAGON_PX; the generated doc names the ray counts).
IMAGE_RUNS     ?= cornell-box-primary cornell-box-ao dragon-primary dragon-ao
SWEEP_CORNELL_PX ?= 96
SWEEP_DRAGON_PX  ?= 128
SWEEP_RUNS     := $(IMAGE_RUNS) $(addprefix hard-,$(HARD_CASES))
SPEED_RAYS     ?= 1024
# local: make -j$(SWEEP_JOBS) on this machine; slurm: one Slurm job array
# (scripts/slurm/sweep-array.sh); `make slurm-up` starts a one-node cluster.
SWEEP_ENGINE   ?= local
# Where PointArea caches its Yosys runs (shared by every sweep and make verilog;
# sweep-slurm-check points it into its own sweep so every area is recomputed).
SWEEP_AREA_CACHE ?= build/area-cache
# Where the report goes: $(SWEEP_DOC).{md,json} and the plots in $(SWEEP_DOC)/.
SWEEP_DOC      ?= docs/reports/speed-vs-error
SWEEP_JAVA     := java -Xss8m -Xmx3g -cp "$$(cat $(SWEEP)/classpath)"
comma := ,
empty :=
space := $(empty) $(empty)

.PHONY: speed-vs-error sweep-jobs sweep-packages sweep-clean

# The report has a recipe line of its own: make runs a line that names $(MAKE)
# even under -n, and `make -n speed-vs-error` must not rewrite the report.
speed-vs-error: setup ## The precision sweep: error, area and speed per number format
	@mkdir -p $(SWEEP) && date +%s > $(SWEEP)/started
	rm -f $(SWEEP)/classpath
	$(MAKE) --no-print-directory $(SWEEP)/classpath
	$(MAKE) --no-print-directory sweep-run-$(SWEEP_ENGINE)
	@start=$$(cat $(SWEEP)/started); end=$$(date +%s); \
	$(BRIDGE) sweep-report --sweep $(SWEEP) --json $(SWEEP_DOC).json --md $(SWEEP_DOC).md --plots $(SWEEP_DOC) \
	  --runtime-note "$(words $(SWEEP_POINTS)) points ($(if $(filter full,$(SWEEP_GRID)),the full grid,SWEEP_GRID=$(SWEEP_GRID))), image runs $(IMAGE_RUNS) (Cornell $(SWEEP_CORNELL_PX)x$(SWEEP_CORNELL_PX), dragon $(SWEEP_DRAGON_PX)x$(SWEEP_DRAGON_PX) pixels), $(SPEED_RAYS) timed rays per run; the last make speed-vs-error took $$(( (end - start + 30) / 60 )) min wall with $(if $(filter slurm,$(SWEEP_ENGINE)),a Slurm job array,make -j$(SWEEP_JOBS)) on $$(nproc) cores on $$(date -u +%Y-%m-%d) (jobs already done are not rerun)"

# The point jobs: what `make -j` runs here, or what a Slurm array runs.
SWEEP_POINT_JOBS := $(addprefix $(SWEEP)/points/,$(addsuffix .json,$(SWEEP_POINTS))) \
            $(if $(HARD_CASES),$(addprefix $(SWEEP)/points/,$(addsuffix .hard.json,$(SWEEP_POINTS)))) \
            $(addprefix $(SWEEP)/area/,$(addsuffix .json,$(SWEEP_POINTS)))
# Their shared inputs, built once before the jobs (two array tasks must never
# race to build the same package).
SWEEP_PACKAGES = $(foreach l,$(SWEEP_USED_LAYOUTS),$(foreach r,$(SWEEP_RUNS),$(SWEEP)/packages/$(l)/$(r)/package.json))
SWEEP_SHARED = $(SWEEP)/classpath $(SWEEP_PACKAGES) \
            $(foreach c,$(HARD_CASES),$(foreach r,embree robust double,$(SWEEP)/hard-ref/$(c)-$(r).json))

.PHONY: sweep-run-local sweep-run-slurm
sweep-run-local:
	$(MAKE) --no-print-directory -j$(SWEEP_JOBS) sweep-jobs
sweep-run-slurm:
	$(MAKE) --no-print-directory -j$(SWEEP_JOBS) $(SWEEP_SHARED)
	scripts/slurm/sweep-array.sh $(SWEEP) SWEEP=$(SWEEP) SPEED_RAYS=$(SPEED_RAYS) "IMAGE_RUNS=$(IMAGE_RUNS)" \
	  SWEEP_CORNELL_PX=$(SWEEP_CORNELL_PX) SWEEP_DRAGON_PX=$(SWEEP_DRAGON_PX) SWEEP_AREA_CACHE=$(SWEEP_AREA_CACHE) -- $(SWEEP_POINT_JOBS)

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
	$(SBT) "compile" "export Runtime/fullClasspath" | tail -1 > $(SWEEP)/classpath.tmp
	@grep -q 'scala-2.13/classes' $(SWEEP)/classpath.tmp || { echo "sweep: sbt did not print the classpath"; exit 1; }
	@mv $(SWEEP)/classpath.tmp $(SWEEP)/classpath

sweep-packages: $(SWEEP_PACKAGES)

# Packages per layout: $(SWEEP)/packages/<layout>/<run>/ (the stem is the layout).
$(SWEEP)/packages/%/cornell-box-primary/package.json: scenes/cornell-box/cornell-box.xml $(IMAGE_STAMP)
	$(BRIDGE) compile $< --out $(@D) --bvh $* --rays primary --width $(SWEEP_CORNELL_PX) --height $(SWEEP_CORNELL_PX)
$(SWEEP)/packages/%/cornell-box-ao/package.json: scenes/cornell-box/cornell-box.xml $(IMAGE_STAMP)
	$(BRIDGE) compile $< --out $(@D) --bvh $* --rays ao --width $$(( $(SWEEP_CORNELL_PX) * 2 / 3 )) --height $$(( $(SWEEP_CORNELL_PX) * 2 / 3 )) --spp 2
$(SWEEP)/packages/%/dragon-primary/package.json: scenes/dragon/dragon.xml $(IMAGE_STAMP)
	$(BRIDGE) compile $< --out $(@D) --bvh $* --rays primary --width $(SWEEP_DRAGON_PX) --height $(SWEEP_DRAGON_PX)
$(SWEEP)/packages/%/dragon-ao/package.json: scenes/dragon/dragon.xml $(IMAGE_STAMP)
	$(BRIDGE) compile $< --out $(@D) --bvh $* --rays ao --width $(SWEEP_DRAGON_PX) --height $(SWEEP_DRAGON_PX) --spp 2
# Hard cases: the sweep's package holds the f64 reference; two more hold Embree's answers without and with ROBUST.
define sweep_hard_package
$(SWEEP)/packages/%/hard-$(1)/package.json: scenes/hard/$(1)/expect.csv $$(IMAGE_STAMP)
	$$(BRIDGE) compile scenes/hard/$(1)/$(1).xml --out $$(@D) --bvh $$* --rays scenes/hard/$(1)/rays.txt --reference double
endef
$(foreach c,$(HARD_CASES),$(eval $(call sweep_hard_package,$(c))))
$(SWEEP)/hard-pkg/%-embree/package.json: scenes/hard/%/expect.csv $(IMAGE_STAMP)
	$(BRIDGE) compile scenes/hard/$*/$*.xml --out $(@D) --rays scenes/hard/$*/rays.txt --reference embree
$(SWEEP)/hard-pkg/%-robust/package.json: scenes/hard/%/expect.csv $(IMAGE_STAMP)
	$(BRIDGE) compile scenes/hard/$*/$*.xml --out $(@D) --rays scenes/hard/$*/rays.txt --reference embree --robust

$(SWEEP)/hard-ref/%-double.json: $(SWEEP)/packages/$(SWEEP_REF_LAYOUT)/hard-%/package.json
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
hard-measure: setup-cargo ## Score Embree, ROBUST, f64 and the f32 trace on every hard case
	@$(MAKE) --no-print-directory $(foreach c,$(HARD_CASES),$(foreach r,embree robust double trace,$(SWEEP)/hard-ref/$(c)-$(r).json))
$(SWEEP)/hard-ref/%-trace.json: $(SWEEP)/packages/$(SWEEP_REF_LAYOUT)/hard-%/package.json
	@mkdir -p $(@D)
	$(BRIDGE) trace --package $(<D) --out $(@D)/$*-trace.csv
	$(BRIDGE) hard-score --package $(<D) --hits $(@D)/$*-trace.csv --expect scenes/hard/$*/expect.csv --out $@

# One point: $* = <layout>-<box>-<tri>-<rne|cons>-<mt|wt>[-grid]. Two jobs per point:
# the image runs (error on every ray, speed in RTL) and the hard cases (error
# only); sweep-report merges `<point>.hard.json` into `<point>.json`.
sweep_point_args = --bvh $(call sweep_field,1,$(1)) --box-float $(call sweep_field,2,$(1)) --tri-float $(call sweep_field,3,$(1)) \
  --rounding $(call sweep_field,4,$(1)) --triangle $(call sweep_field,5,$(1)) \
  $(if $(call sweep_field,6,$(1)),--box-test $(call sweep_field,6,$(1)))
# The $$(...) prerequisites below use .SECONDEXPANSION (set in the Makefile).
$(SWEEP)/points/%.hard.json: | $$(foreach c,$(HARD_CASES),$(SWEEP)/packages/$$(call sweep_field,1,$$*)/hard-$$(c)/package.json) $(SWEEP)/classpath
	@mkdir -p $(SWEEP)/logs
	$(SWEEP_JAVA) rtaccel.sweep.SweepPoint $(call sweep_point_args,$*) --sweep $(SWEEP) --group hard \
	  --runs $(subst $(space),$(comma),$(addprefix hard-,$(HARD_CASES))) > $(SWEEP)/logs/point-$*.hard.log 2>&1 \
	  || { tail -30 $(SWEEP)/logs/point-$*.hard.log; exit 1; }
	@tail -1 $(SWEEP)/logs/point-$*.hard.log
$(SWEEP)/points/%.json: | $$(foreach r,$(IMAGE_RUNS),$(SWEEP)/packages/$$(call sweep_field,1,$$*)/$$(r)/package.json) $(SWEEP)/classpath
	@mkdir -p $(SWEEP)/logs
	$(SWEEP_JAVA) rtaccel.sweep.SweepPoint $(call sweep_point_args,$*) --sweep $(SWEEP) --runs $(subst $(space),$(comma),$(IMAGE_RUNS)) \
	  --speed-runs $(subst $(space),$(comma),$(IMAGE_RUNS)) --speed-rays $(SPEED_RAYS) > $(SWEEP)/logs/point-$*.log 2>&1 \
	  || { tail -30 $(SWEEP)/logs/point-$*.log; exit 1; }
	@tail -1 $(SWEEP)/logs/point-$*.log
$(SWEEP)/area/%.json: | $(SWEEP)/classpath
	@mkdir -p $(SWEEP)/logs
	$(SWEEP_JAVA) rtaccel.tools.PointArea $(call sweep_point_args,$*) --cache $(SWEEP_AREA_CACHE) --out $@ > $(SWEEP)/logs/area-$*.log 2>&1 || { tail -30 $(SWEEP)/logs/area-$*.log; exit 1; }
	@tail -1 $(SWEEP)/logs/area-$*.log

sweep-clean: ## Remove the sweep's outputs (keeps the Yosys cache)
	rm -rf $(SWEEP)
