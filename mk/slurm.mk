# A one-node Slurm cluster on this machine: `make speed-vs-error
# SWEEP_ENGINE=slurm` submits the sweep's point jobs to Slurm as one job array.
# On a real cluster, skip slurm-up: set SLURM_CONF or use the site's defaults,
# and pass sbatch options in SWEEP_SLURM_ARGS (the repository must be on a
# filesystem the nodes share).
.PHONY: setup-slurm slurm-up slurm-down

setup-slurm: ## Install Slurm and munge from Debian, if missing
	@missing=""; for p in slurm-wlm munge; do \
	  dpkg-query -W -f='$${Status}' $$p 2>/dev/null | grep -q "install ok installed" || missing="$$missing $$p"; done; \
	  if [ -n "$$missing" ]; then echo "setup-slurm: installing$$missing"; \
	    SUDO=""; [ "$$(id -u)" = 0 ] || SUDO=sudo; \
	    $$SUDO apt-get update -qq && DEBIAN_FRONTEND=noninteractive $$SUDO apt-get install -y -qq $$missing >/dev/null; \
	  else echo "setup-slurm: slurm-wlm and munge present"; fi

slurm-up: setup-slurm ## Start a one-node Slurm cluster on this machine
	@scripts/slurm/local-cluster.sh up

slurm-down: ## Stop the one-node Slurm cluster
	@scripts/slurm/local-cluster.sh down

# The Slurm sweep's check, outside `make test` (it needs root and starts services):
# start the one-node cluster, run SWEEP_CHECK_POINTS through
# `make speed-vs-error SWEEP_ENGINE=slurm` into a fresh $(SWEEP_CHECK) (its own
# Yosys cache, so every area is recomputed; its report goes to
# $(SWEEP_CHECK)/report, not docs/), stop the cluster even on failure, then
# compare every result file with the make -j sweep $(SWEEP_CHECK_REF) made with
# the same settings (scripts/slurm/compare-sweeps.py: exit 1 on any difference).
# The wall time and the comparison land in $(SWEEP_CHECK)/check.txt.
SWEEP_CHECK        ?= $(BUILD)/sweep-slurm
SWEEP_CHECK_REF    ?= $(BUILD)/sweep6
SWEEP_CHECK_POINTS ?= 4-e8m23-e8m23-cons-wt 4q-e8m10-e8m23-cons-wt
SWEEP_CHECK_VARS   ?= SWEEP_CORNELL_PX=48 SWEEP_DRAGON_PX=64 SPEED_RAYS=256
.PHONY: sweep-slurm-check sweep-compare

sweep-slurm-check: setup setup-slurm ## Check that a Slurm sweep equals the make -j sweep (needs root)
	scripts/slurm/sweep-check.sh $(SWEEP_CHECK) $(SWEEP_CHECK_REF) "$(SWEEP_CHECK_POINTS)" $(SWEEP_CHECK_VARS)

sweep-compare: ## Compare two sweep directories field by field: A=<dir> B=<dir>
	@[ -n "$(A)" ] && [ -n "$(B)" ] || { echo "usage: make sweep-compare A=<sweep dir> B=<sweep dir> [POINTS=\"<point> ...\"]"; exit 2; }
	scripts/slurm/compare-sweeps.py $(A) $(B) $(POINTS)
