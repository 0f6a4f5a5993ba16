# rtaccel: the user's interface. `make help` lists the targets.
# Every user-facing target depends on `setup`, so each one works on a fresh
# Debian machine: setup installs only what is missing and is cheap when warm.
SHELL := /bin/bash
.SHELLFLAGS := -euo pipefail -c
.DEFAULT_GOAL := help

SBT       := ./sbt
CARGO     := cargo
BRIDGE_MANIFEST := nori-bridge/Cargo.toml
BRIDGE    := nori-bridge/target/release/nori-bridge
BUILD     := build
# The memory image's format version (docs/memory-format.md; rtaccel.scene.MemoryImage.Version, checked by
# MemoryImageSpec). Rules that keep a compiled package depend on this stamp, so a new format compiles them again.
IMAGE_FORMAT := 3
IMAGE_STAMP  := $(BUILD)/.image-format-$(IMAGE_FORMAT)
SBT_LAUNCH_VERSION := $(shell sed -n 's/^sbt.version *= *//p' project/build.properties)
SBT_LAUNCH_JAR := $(HOME)/.m2/repository/org/scala-sbt/sbt-launch/$(SBT_LAUNCH_VERSION)/sbt-launch-$(SBT_LAUNCH_VERSION).jar
# libeigen3-dev: the Nori drop-in builds against real Eigen in its test (nori-accel/stub/include/nori/common.h).
APT_PACKAGES := verilator yosys libembree-dev maven pkg-config fonts-dejavu-core libeigen3-dev

.PHONY: help help-all setup setup-apt setup-sbt setup-cargo test test-scala test-slow test-rust test-hls demo verilog regress clean

# `make help`: the main targets by task, one line each (kept by hand, 25 lines
# at most); `make help-all`: every target's `## ` line, sorted. Each target's
# options are in docs/make-targets.md.
help: ## The main targets
	@printf '%s\n' \
	  'rtaccel: a Chisel generator for an FPGA ray-tracing accelerator. Guide: docs/README.md' \
	  '' \
	  'Start' \
	  '  make demo                  The Cornell box through the RTL, checked against Embree, with images' \
	  '  make test                  Every test: what CI runs (about 40 min on 2 cores)' \
	  '  make setup                 Install what is missing; every target runs it first' \
	  'Your scene' \
	  '  make regress SCENE=<xml>   Trace a Nori scene in RTL; every ray checked against golden + Embree' \
	  '  make render SCENE=<xml>    A shaded image from the accelerator hits, beside Embree and a diff' \
	  'Hardware' \
	  '  make verilog               SystemVerilog for the ZC706, lint, Yosys area and Fmax estimate' \
	  '  make formal                Bounded model check of the core control path' \
	  'Measure' \
	  '  make bench                 Rays/cycle per layout and memory; ZC706 estimate against Embree' \
	  '  make speed-vs-error        The precision sweep: error, area and speed per number format' \
	  'More' \
	  '  make help-all              Every target, one line each (options: docs/make-targets.md)' \
	  '  make clean                 Remove build outputs (keeps toolchains and caches)'

help-all: ## Every target, one line each
	@grep -hE '^[a-zA-Z0-9_.-]+:.*## ' $(MAKEFILE_LIST) | sort -u | \
	  awk 'BEGIN {FS = ":.*## "}; {printf "  make %-21s %s\n", $$1, $$2}'

setup: setup-apt setup-sbt setup-cargo ## Install what is missing (apt, sbt launcher, Rust build); idempotent

setup-apt: ## Install the Debian packages rtaccel needs, if missing
	@missing=""; for p in $(APT_PACKAGES); do \
	  dpkg-query -W -f='$${Status}' $$p 2>/dev/null | grep -q "install ok installed" || missing="$$missing $$p"; done; \
	  command -v javac >/dev/null || missing="$$missing openjdk-17-jdk-headless"; \
	  command -v cargo >/dev/null || missing="$$missing cargo"; \
	  if [ -n "$$missing" ]; then \
	    echo "setup: installing$$missing"; \
	    SUDO=""; [ "$$(id -u)" = 0 ] || SUDO=sudo; \
	    $$SUDO apt-get update -qq && DEBIAN_FRONTEND=noninteractive $$SUDO apt-get install -y -qq $$missing >/dev/null; \
	  else echo "setup: apt packages present"; fi

setup-sbt: setup-apt ## Fetch the sbt launcher jar from Maven Central, if missing
	@if [ -f "$(SBT_LAUNCH_JAR)" ]; then echo "setup: sbt launcher $(SBT_LAUNCH_VERSION) present"; \
	else mvn -q dependency:get -Dartifact=org.scala-sbt:sbt-launch:$(SBT_LAUNCH_VERSION) -Dtransitive=false; fi

# An older cargo (Debian 12's is 1.63) cannot build nori-bridge's dependencies: say so, not cargo's parse errors.
setup-cargo: setup-apt ## Build nori-bridge (release) from crates.io
	@need=$$(sed -n 's/^rust-version *= *"\(.*\)"/\1/p' $(BRIDGE_MANIFEST)); \
	  have=$$($(CARGO) --version | awk '{print $$2}'); \
	  if [ "$$(printf '%s\n%s\n' "$$need" "$$have" | sort -V | head -n1)" != "$$need" ]; then \
	    echo "setup: $(BRIDGE_MANIFEST) needs Rust $$need or newer (its rust-version); $$(command -v $(CARGO)) is cargo $$have." >&2; \
	    echo "setup: install Rust $$need or newer with rustup (https://rustup.rs) and put ~/.cargo/bin first on PATH." >&2; \
	    exit 1; fi
	@$(CARGO) build --release --quiet --manifest-path $(BRIDGE_MANIFEST)

# The HLS test benches run first: they write hls/build/vectors/*.out, which the
# Chisel datapath specs compare against bit for bit.
test: setup test-hls test-scala test-rust ## Every test: what CI runs (about 40 min on 2 cores)
	@echo "make test: all test suites passed"

test-scala: setup-sbt ## The Chisel specs, less those tagged SlowTest
	$(SBT) scalafmtCheckAll Test/scalafmtCheckAll scalafmtSbtCheck "testOnly -- -l rtaccel.SlowTest"

test-slow: setup ## The Chisel specs tagged SlowTest (whole-core checks make test covers in part), not in make test
	$(SBT) "testOnly -- -n rtaccel.SlowTest"

test-rust: setup-cargo ## The nori-bridge tests (cargo test)
	$(CARGO) test --release --manifest-path $(BRIDGE_MANIFEST)

test-hls: setup-apt ## The HLS twins' C-simulation test benches
	$(MAKE) -C hls test

demo: setup ## The Cornell box through the RTL against Embree, with images
	@./scripts/demo.sh

# SCENE= (or an already compiled PACKAGE=) sizes the hardware to that scene and
# its rays (RAYS=primary by default) and reports the area saved (sized.md).
VERILOG_PACKAGE = $(or $(PACKAGE),$(if $(SCENE),$(BUILD)/verilog/scene))
verilog: setup ## SystemVerilog for the ZC706, lint, area and Fmax estimate
	$(if $(SCENE),$(BRIDGE) compile $(SCENE) --out $(BUILD)/verilog/scene --rays $(or $(RAYS),primary) --bvh $(or $(BVH),4))
	$(SBT) "runMain rtaccel.tools.EmitVerilog --out $(BUILD)/verilog --bvh $(or $(BVH),4) --float $(or $(FLOAT),e8m23)$(if $(BOX_FLOAT), --box-float $(BOX_FLOAT))$(if $(TRI_FLOAT), --tri-float $(TRI_FLOAT)) --triangle $(or $(TRIANGLE),watertight) --rounding $(or $(ROUNDING),conservative)$(if $(BOX_TEST), --box-test $(BOX_TEST))$(if $(IDS), --ids $(IDS)) --synth $(or $(SYNTH),1) --system $(or $(SYSTEM),1)$(if $(CORES), --cores $(CORES))$(if $(VERILOG_PACKAGE), --package $(VERILOG_PACKAGE))"

# The longest path of one unit of the emitted design, net by net (docs/fmax.md).
fmax-path: setup-sbt ## One unit's longest path, every net with its arrival: UNIT=<module> [SV=build/verilog/rtaccel_system.sv]
	@test -n "$(UNIT)" || { echo "fmax-path: set UNIT=<module name from build/verilog/resources.md>"; exit 2; }
	$(SBT) "runMain rtaccel.tools.FmaxPath $(or $(SV),$(BUILD)/verilog/rtaccel_system.sv) $(UNIT)"

regress: setup ## Trace a scene's rays in RTL, each checked: SCENE=<scene.xml>
	@scripts/regress.sh

clean: ## Remove build outputs (keeps toolchains and caches)
	rm -rf $(BUILD) target project/target project/project test_run_dir
	$(MAKE) -C hls clean
	$(CARGO) clean --manifest-path $(BRIDGE_MANIFEST)

# Secondary expansion ($$ in prerequisites, expanded again per target) is a
# global switch that holds from where it appears to the end of the makefiles:
# set here, before the includes, so that it holds for every mk file alike
# rather than for those that sort after whichever one set it (mk/sweep.mk
# uses it for prerequisites that depend on the stem).
.SECONDEXPANSION:

# Area-specific targets (floating point, scenes, benchmarks) live in mk/*.mk.
-include mk/*.mk

$(IMAGE_STAMP):
	@mkdir -p $(@D) && touch $@
