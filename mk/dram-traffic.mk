# DRAM traffic on paper: bytes per ray of the memory-side candidates (node layouts, triangle records, paired hits,
# store sizes, a cache with and without reordered rays, treelet ray queues, the PS DDR as a second channel) from the
# golden walk's reads -> docs/reports/dram-traffic.md (method and reading: docs/dram-traffic.md).
# Runs are <scene>-<rays>, the scene at scenes/<scene>/<scene>.xml; each is compiled by nori-bridge once per layout
# into build/dram-traffic/<layout>/<run>.
DRAM_TRAFFIC_RUNS    ?= dragon-primary dragon-shadow dragon-ao
DRAM_TRAFFIC_LAYOUTS := 4 4q 8q
DRAM_TRAFFIC_DIR     := $(BUILD)/dram-traffic
DRAM_TRAFFIC_OUT     ?= docs/reports/dram-traffic.md
dram_traffic_pkgs    := $(foreach l,$(DRAM_TRAFFIC_LAYOUTS),$(foreach r,$(DRAM_TRAFFIC_RUNS),$(DRAM_TRAFFIC_DIR)/$(l)/$(r)/image.bin))

# $(DRAM_TRAFFIC_DIR)/<layout>/<scene>-<rays>/image.bin: the last '-' splits scene from ray kind.
$(DRAM_TRAFFIC_DIR)/%/image.bin: | setup bridge-scenes
	@set -- $(subst /, ,$*); layout=$$1; run=$$2; scene=$${run%-*}; rays=$${run##*-}; \
	  $(BRIDGE) compile scenes/$$scene/$$scene.xml --out $(DRAM_TRAFFIC_DIR)/$$layout/$$run --rays $$rays --bvh $$layout

.PHONY: dram-traffic-study
dram-traffic-study: setup $(dram_traffic_pkgs) ## DRAM bytes per ray of each memory-side candidate on paper, with Mrays/s bounds -> docs/reports/dram-traffic.md [DRAM_TRAFFIC_RUNS= MAX_RAYS=2048]
	$(SBT) "runMain rtaccel.study.DramTrafficStudy --root $(DRAM_TRAFFIC_DIR) --max-rays $(or $(MAX_RAYS),2048) --runs $(call bench_list,$(DRAM_TRAFFIC_RUNS)) --out $(DRAM_TRAFFIC_OUT) --command 'make dram-traffic-study MAX_RAYS=$(or $(MAX_RAYS),2048)'"
