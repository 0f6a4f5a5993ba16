#!/usr/bin/env bash
# Runs the sweep's point jobs as one Slurm job array and waits for it:
#   sweep-array.sh <sweep dir> <make variable assignments...> -- <target files...>
# Each array task builds one target file with this repository's own make rule
# (`make <file>`), so a point computed through Slurm is the same command as one
# computed by `make -j`. Targets that exist already are skipped, as make would.
# Assumes the repository (and the sweep directory) sit on a filesystem every
# node sees, as on the one-node cluster of local-cluster.sh; the shared inputs
# (classpath, packages, hard-case references) are built before submission.
# SWEEP_SLURM_ARGS adds sbatch options (partition, account, time limit).
set -euo pipefail
sweep=$1; shift
vars=()
while [ "$#" -gt 0 ] && [ "$1" != "--" ]; do vars+=("$1"); shift; done
[ "${1:-}" = "--" ] || { echo "sweep-array: usage: $0 <sweep dir> [VAR=value...] -- <targets...>" >&2; exit 2; }
shift
# The one-node cluster of `make slurm-up` keeps its configuration in build/slurm.
if [ -z "${SLURM_CONF:-}" ] && [ ! -f /etc/slurm/slurm.conf ] && [ -f build/slurm/slurm.conf ]; then
  export SLURM_CONF=$PWD/build/slurm/slurm.conf
fi
command -v sbatch >/dev/null || { echo "sweep-array: sbatch not found; install Slurm (make setup-slurm) or use SWEEP_ENGINE=local" >&2; exit 1; }
todo=()
for t in "$@"; do [ -e "$t" ] || todo+=("$t"); done
mkdir -p "$sweep/slurm"
if [ "${#todo[@]}" -eq 0 ]; then echo "sweep-array: all $# jobs already done"; exit 0; fi
list=$sweep/slurm/targets.txt
printf '%s\n' "${todo[@]}" > "$list"
repo=$(pwd)
# Each assignment quoted for the task's shell (IMAGE_RUNS holds spaces).
quoted=$(printf '%q ' "${vars[@]}")
n=${#todo[@]}
echo "sweep-array: submitting $n jobs as one Slurm array (list: $list)"
# -c 1 and 4 GB per task: each job is one single-threaded java (-Xmx3g) or Yosys run.
sbatch --wait --job-name=rtaccel-sweep --array=0-$((n - 1)) -c 1 --mem=4G \
  --output="$sweep/slurm/%A_%a.log" ${SWEEP_SLURM_ARGS:-} \
  --wrap "cd '$repo' && t=\$(sed -n \"\$((SLURM_ARRAY_TASK_ID + 1))p\" '$list') && echo \"task \$SLURM_ARRAY_TASK_ID: \$t\" && make --no-print-directory $quoted SWEEP_ENGINE=local \"\$t\"" \
  || true
missing=0
for t in "${todo[@]}"; do
  if [ ! -e "$t" ]; then
    missing=$((missing + 1))
    i=$(grep -nxF "$t" "$list" | cut -d: -f1); i=$((i - 1))
    echo "sweep-array: job $i did not produce $t; its log:" >&2
    tail -20 "$sweep"/slurm/*_"$i".log >&2 || true
  fi
done
[ "$missing" -eq 0 ] || { echo "sweep-array: $missing of $n jobs failed" >&2; exit 1; }
echo "sweep-array: all $n jobs done"
