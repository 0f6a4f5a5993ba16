# DRAM traffic on paper: bytes per ray of the memory-side candidates (node layouts, triangle records, paired hits,
# store sizes, a cache with and without reordered rays, treelet ray queues, the PS DDR as a second channel) from the
# golden walk's reads -> docs/reports/dram-traffic.md (method and reading: docs/dram-traffic.md).
# Runs are <scene>-<rays>, the scene at scenes/<scene>/<scene>.xml, or <scene><N>-<rays> for its camera at N x N
# pixels (e.g. dragon128-ao: the AO rays of a 128 x 128 frame); each is compiled by nori-bridge once per layout
# into build/dram-traffic/<layout>/<run>. DRAM_TRAFFIC_ONLY= names candidates by key (rtaccel.study.Candidates).
# m_axi's R-channel bound is taken at the Fmax estimate of `make verilog` (run first, cached), as make bench does.
DRAM_TRAFFIC_RUNS    ?= dragon-primary dragon-shadow dragon-ao monastery-primary monastery-shadow monastery-ao
DRAM_TRAFFIC_LAYOUTS := 4 4q 8q
DRAM_TRAFFIC_DIR     := $(BUILD)/dram-traffic
DRAM_TRAFFIC_OUT     ?= docs/reports/dram-traffic.md
dram_traffic_pkgs    := $(foreach l,$(DRAM_TRAFFIC_LAYOUTS),$(foreach r,$(DRAM_TRAFFIC_RUNS),$(DRAM_TRAFFIC_DIR)/$(l)/$(r)/image.bin))

# $(DRAM_TRAFFIC_DIR)/<layout>/<scene>-<rays>/image.bin: the last '-' splits scene from ray kind.
$(DRAM_TRAFFIC_DIR)/%/image.bin: $(IMAGE_STAMP) | setup bridge-scenes bridge-scenes-monastery
	@set -- $(subst /, ,$*); layout=$$1; run=$$2; scene=$${run%-*}; rays=$${run##*-}; \
	  size=$$(echo $$scene | sed -n 's/.*[^0-9]\([0-9][0-9]*\)$$/\1/p'); scene=$${scene%$$size}; \
	  $(BRIDGE) compile scenes/$$scene/$$scene.xml --out $(DRAM_TRAFFIC_DIR)/$$layout/$$run --rays $$rays --bvh $$layout \
	    $${size:+--width $$size --height $$size}

.PHONY: dram-traffic-study
dram-traffic-study: setup verilog $(dram_traffic_pkgs) ## DRAM bytes per ray of each memory-side candidate on paper, with Mrays/s bounds -> docs/reports/dram-traffic.md [DRAM_TRAFFIC_RUNS= MAX_RAYS=2048 DRAM_TRAFFIC_ONLY= DRAM_TRAFFIC_OUT=]
	$(SBT) "runMain rtaccel.study.DramTrafficStudy --root $(DRAM_TRAFFIC_DIR) --max-rays $(or $(MAX_RAYS),2048) --runs $(call bench_list,$(DRAM_TRAFFIC_RUNS)) --out $(DRAM_TRAFFIC_OUT)$(if $(DRAM_TRAFFIC_ONLY), --only $(call bench_list,$(DRAM_TRAFFIC_ONLY)))"
