#!/usr/bin/env bash
# The check behind `make sweep-slurm-check`: a Slurm sweep equals a
# `make -j` sweep. Starts the one-node cluster, runs the points through
# `make speed-vs-error SWEEP_ENGINE=slurm` into a fresh sweep directory (its own
# Yosys cache, so every area is recomputed; the report goes into that directory,
# not docs/), stops the cluster even on failure, and compares every result file
# with the reference sweep (compare-sweeps.py; exit 1 on any difference).
#   sweep-check.sh <new sweep dir> <reference sweep dir> "<points>" [VAR=value...]
# A script, not a recipe line: `make -n sweep-slurm-check` must only print it
# (make runs a recipe line that names $(MAKE) even under -n).
set -euo pipefail
new=$1 ref=$2 points=$3; shift 3
[ -d "$ref/points" ] || { echo "sweep-check: no $ref/points; make it first: make speed-vs-error SWEEP=$ref SWEEP_POINTS=\"$points\" $*" >&2; exit 1; }
rm -rf "$new"; mkdir -p "$new"
start=$(date +%s)
trap 'scripts/slurm/local-cluster.sh down' EXIT
scripts/slurm/local-cluster.sh up
"${MAKE:-make}" --no-print-directory speed-vs-error SWEEP="$new" SWEEP_ENGINE=slurm SWEEP_JOBS=1 SWEEP_POINTS="$points" "$@" \
  SWEEP_AREA_CACHE="$new/area-cache" SWEEP_DOC="$new/report/speed-vs-error"
end=$(date +%s)
echo "sweep-check: $(wc -w <<< "$points") points through Slurm in $((end - start)) s wall, cluster start and report included ($(date -u +%Y-%m-%dT%H:%MZ), $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg))" | tee "$new/check.txt"
scripts/slurm/compare-sweeps.py "$ref" "$new" $points | tee -a "$new/check.txt"
