# A one-node Slurm cluster on this machine (issue 15): `make speed-vs-error
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

slurm-up: setup-slurm ## Start a one-node Slurm cluster on this machine (build/slurm/); then: make speed-vs-error SWEEP_ENGINE=slurm
	@scripts/slurm/local-cluster.sh up

slurm-down: ## Stop the one-node Slurm cluster
	@scripts/slurm/local-cluster.sh down
