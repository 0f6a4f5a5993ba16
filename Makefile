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
SBT_LAUNCH_VERSION := $(shell sed -n 's/^sbt.version *= *//p' project/build.properties)
SBT_LAUNCH_JAR := $(HOME)/.m2/repository/org/scala-sbt/sbt-launch/$(SBT_LAUNCH_VERSION)/sbt-launch-$(SBT_LAUNCH_VERSION).jar
# libeigen3-dev: the Nori drop-in builds against real Eigen in its test (nori-accel/stub/include/nori/common.h).
APT_PACKAGES := verilator yosys libembree-dev maven pkg-config fonts-dejavu-core libeigen3-dev

.PHONY: help setup setup-apt setup-sbt setup-cargo test test-scala test-rust test-hls demo verilog regress clean

help: ## List the targets and what each does
	@grep -hE '^[a-zA-Z0-9_.-]+:.*## ' $(MAKEFILE_LIST) | sort -u | \
	  awk 'BEGIN {FS = ":.*## "}; {printf "  make %-18s %s\n", $$1, $$2}'

setup: setup-apt setup-sbt setup-cargo ## Install what is missing (apt packages, sbt launcher, Rust build); idempotent

setup-apt: ## Install the Debian packages rtaccel needs, if any is missing
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

setup-cargo: setup-apt ## Build nori-bridge (release), fetching crates from crates.io
	@$(CARGO) build --release --quiet --manifest-path $(BRIDGE_MANIFEST)

# The HLS test benches run first: they write hls/build/vectors/*.out, which the
# Chisel datapath specs compare against bit for bit.
test: setup test-hls test-scala test-rust ## Run every test: the hls/ C-simulation tests, sbt test, cargo test
	@echo "make test: all test suites passed"

test-scala: setup-sbt ## Chisel/chiseltest specs (treadle and Verilator)
	$(SBT) test

test-rust: setup-cargo ## nori-bridge tests
	$(CARGO) test --release --manifest-path $(BRIDGE_MANIFEST)

test-hls: setup-apt ## Build and run the HLS twins' C-simulation test benches
	$(MAKE) -C hls test

demo: setup ## The main job on the default shipped scene
	@./scripts/demo.sh

# SCENE= (or an already compiled PACKAGE=) sizes the hardware to that scene and
# its rays (RAYS=primary by default) and reports the area saved (sized.md).
VERILOG_PACKAGE = $(or $(PACKAGE),$(if $(SCENE),$(BUILD)/verilog/scene))
verilog: setup ## SystemVerilog for the ZC706 into build/verilog/, lint, Yosys resource table [BVH=4|2|8|nori|4q|8q FLOAT=eXmY|auto BOX_FLOAT= TRI_FLOAT= TRIANGLE= ROUNDING=conservative|rne IDS=<ray IDs per core> SYNTH=0 SYSTEM=0|1 CORES=<n> SCENE=<scene.xml> or PACKAGE=<compiled dir>]
	$(if $(SCENE),$(BRIDGE) compile $(SCENE) --out $(BUILD)/verilog/scene --rays $(or $(RAYS),primary) --bvh $(or $(BVH),4))
	$(SBT) "runMain rtaccel.tools.EmitVerilog --out $(BUILD)/verilog --bvh $(or $(BVH),4) --float $(or $(FLOAT),e8m23)$(if $(BOX_FLOAT), --box-float $(BOX_FLOAT))$(if $(TRI_FLOAT), --tri-float $(TRI_FLOAT)) --triangle $(or $(TRIANGLE),watertight) --rounding $(or $(ROUNDING),conservative)$(if $(IDS), --ids $(IDS)) --synth $(or $(SYNTH),1) --system $(or $(SYSTEM),1)$(if $(CORES), --cores $(CORES))$(if $(VERILOG_PACKAGE), --package $(VERILOG_PACKAGE))"

regress: setup ## Scene regression: make regress SCENE=scenes/x/x.xml [RAYS= FLOAT= BOX_FLOAT= TRI_FLOAT= TRIANGLE= ROUNDING=conservative|rne MEMORY=ddr|onchip MEM_LATENCY=<ns> FABRIC_MHZ=200 IDS= STACK= OUT= WAVES=1 SIM=chiseltest|cpp]
	@scripts/regress.sh

clean: ## Remove build outputs (keeps downloaded toolchains and caches)
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
