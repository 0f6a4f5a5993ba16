# The system top under Verilator against independent AXI models:
# cocotb + cocotbext-axi (AxiRam on m_axi, AxiLiteMaster on s_axi), tests in
# src/test/cocotb/. `make test` runs them for one core (COCOTB_CORES=1).
#
# Versions (src/test/cocotb/requirements.txt): cocotb 1.8.1 is the newest
# release documented for Debian's Verilator 5.006 (1.9 documents 5.022+, 2.x
# stops at its makefile's check for 5.036). The venv lives in ~/.cache (kept
# by `make clean`), keyed by the requirements file's hash, so a warm setup
# costs one `sha256sum`.

COCOTB_DIR   := src/test/cocotb
COCOTB_REQ   := $(COCOTB_DIR)/requirements.txt
COCOTB_VENV  := $(HOME)/.cache/rtaccel/cocotb-venv
COCOTB_BUILD := $(BUILD)/cocotb
# One Verilator build per configuration: N cores (the core: FP32, 8 ray IDs, sized to the Cornell box).
# Default 1 (in `make test`): measured 2 min 48 s with a cold Verilator build,
# 5 min 58 s for COCOTB_CORES="1 2" (2026-11-30, shared 2-core machine, load 3-5).
COCOTB_CORES ?= 1
COCOTB_SCENE := scenes/cornell-box/cornell-box.xml
# 16 x 12 camera rays and one shadow ray per primary hit: small enough for
# cocotb's speed, every ray checked against the golden model.
COCOTB_RAYS_W := 16
COCOTB_RAYS_H := 12

.PHONY: setup-cocotb test-cocotb

test: test-cocotb

setup-cocotb: setup-apt ## Python venv with the pinned cocotb and cocotbext-axi
	@want=$$(sha256sum $(COCOTB_REQ) | cut -c1-16); \
	if [ "$$(cat $(COCOTB_VENV)/.requirements 2>/dev/null)" = "$$want" ]; then \
	  echo "setup: cocotb venv present ($(COCOTB_VENV))"; \
	else \
	  echo "setup: cocotb venv into $(COCOTB_VENV)"; \
	  python3 -m venv --help >/dev/null 2>&1 || { SUDO=""; [ "$$(id -u)" = 0 ] || SUDO=sudo; \
	    $$SUDO apt-get update -qq && DEBIAN_FRONTEND=noninteractive $$SUDO apt-get install -y -qq python3-venv >/dev/null; }; \
	  rm -rf $(COCOTB_VENV) && python3 -m venv $(COCOTB_VENV) && \
	  $(COCOTB_VENV)/bin/pip install -q --disable-pip-version-check -r $(COCOTB_REQ) && \
	  echo "$$want" > $(COCOTB_VENV)/.requirements; \
	fi

# The scene packages: Cornell box, 4-wide nodes (the ZC706 layout), primary and shadow rays.
$(COCOTB_BUILD)/pkg/primary/image.bin: $(BRIDGE) $(COCOTB_SCENE) mk/cocotb.mk
	$(BRIDGE) compile $(COCOTB_SCENE) --out $(@D) --rays primary --bvh 4 --width $(COCOTB_RAYS_W) --height $(COCOTB_RAYS_H)
$(COCOTB_BUILD)/pkg/shadow/image.bin: $(BRIDGE) $(COCOTB_SCENE) mk/cocotb.mk
	$(BRIDGE) compile $(COCOTB_SCENE) --out $(@D) --rays shadow --bvh 4 --width $(COCOTB_RAYS_W) --height $(COCOTB_RAYS_H)

test-cocotb: setup-sbt setup-cargo setup-cocotb $(COCOTB_BUILD)/pkg/primary/image.bin $(COCOTB_BUILD)/pkg/shadow/image.bin ## The system top under cocotb + cocotbext-axi (part of make test)
	$(SBT) "runMain rtaccel.cocotb.Prepare --out $(COCOTB_BUILD) --cores $(subst $(space),$(comma),$(strip $(COCOTB_CORES))) --packages $(COCOTB_BUILD)/pkg/primary,$(COCOTB_BUILD)/pkg/shadow"
	@# cocotb 1.8's makefile exits 0 when a test fails: results.xml decides.
	@for n in $(COCOTB_CORES); do \
	  echo "test-cocotb: rtaccel_system with $$n core(s)"; \
	  rm -f $(COCOTB_BUILD)/n$$n/results.xml; \
	  PATH=$(COCOTB_VENV)/bin:$$PATH $(MAKE) --no-print-directory -C $(COCOTB_DIR) \
	    CONFIG_DIR=$(CURDIR)/$(COCOTB_BUILD)/n$$n || exit 1; \
	  r=$(COCOTB_BUILD)/n$$n/results.xml; \
	  grep -q "<testcase" $$r 2>/dev/null || { echo "test-cocotb: $$r: no test ran"; exit 1; }; \
	  if grep -qE "<(failure|error)" $$r; then echo "test-cocotb: a test failed with $$n core(s) (see $$r and the log above)"; exit 1; fi; \
	done
	@echo "test-cocotb: passed ($(COCOTB_CORES) core configurations)"
