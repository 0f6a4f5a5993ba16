#!/usr/bin/env bash
# A one-node Slurm cluster on this machine, for running the sweep's point jobs
# through a real batch scheduler (SWEEP_ENGINE=slurm) where no cluster exists.
# Everything it writes lives under $SLURM_DIR (build/slurm); the only system
# state it touches is the munge daemon, which Slurm needs for authentication.
#   local-cluster.sh up    start munged, slurmctld and slurmd; wait until the node is idle
#   local-cluster.sh down  stop slurmd and slurmctld, and munged if `up` started it
#   local-cluster.sh env   print the SLURM_CONF line to use the cluster from a shell
set -euo pipefail
SLURM_DIR=$(realpath -m "${SLURM_DIR:-build/slurm}")
CONF=$SLURM_DIR/slurm.conf
NODE=$(hostname -s)

die() { echo "slurm: $*" >&2; exit 1; }

write_conf() {
  mkdir -p "$SLURM_DIR"/{state,spool,log}
  local cpus mem_mb
  # SLURM_NODE_CPUS (default: the machine's cores, at most 2) caps how many
  # 1-CPU sweep tasks run at once, so the cluster never takes a shared
  # machine's every core.
  cpus=${SLURM_NODE_CPUS:-$(( $(nproc) < 2 ? $(nproc) : 2 ))}
  # Leave 1 GiB to the system; Slurm refuses a node that reports less than RealMemory.
  mem_mb=$(( $(awk '/MemTotal/ {print int($2/1024)}' /proc/meminfo) - 1024 ))
  cat > "$CONF" <<CONF
# Written by scripts/slurm/local-cluster.sh: one node, the machine itself.
ClusterName=rtaccel
SlurmctldHost=$NODE
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
StateSaveLocation=$SLURM_DIR/state
SlurmdSpoolDir=$SLURM_DIR/spool
SlurmctldPidFile=$SLURM_DIR/slurmctld.pid
SlurmdPidFile=$SLURM_DIR/slurmd.pid
SlurmctldLogFile=$SLURM_DIR/log/slurmctld.log
SlurmdLogFile=$SLURM_DIR/log/slurmd.log
SlurmctldPort=6817
SlurmdPort=6818
# No cgroup hierarchy is assumed (containers often lack a writable one).
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU_Memory
MpiDefault=none
ReturnToService=2
NodeName=$NODE CPUs=$cpus RealMemory=$mem_mb State=UNKNOWN
PartitionName=rtaccel Nodes=$NODE Default=YES MaxTime=INFINITE State=UP
CONF
}

start_munge() {
  # A working munged (not just a process name: a dying one lingers as a zombie).
  if munge -n 2>/dev/null | unmunge >/dev/null 2>&1; then return; fi
  [ -f /etc/munge/munge.key ] || { mkdir -p /etc/munge; dd if=/dev/urandom bs=1 count=1024 of=/etc/munge/munge.key 2>/dev/null; }
  chown -R munge:munge /etc/munge /var/lib/munge /var/log/munge 2>/dev/null || true
  chmod 0400 /etc/munge/munge.key
  mkdir -p /run/munge && chown munge:munge /run/munge
  if id munge >/dev/null 2>&1; then su -s /bin/sh munge -c "munged" || munged --force
  else munged --force; fi
  # Ours to stop in `down` (a munged that was already running is left alone).
  touch "$SLURM_DIR/munged.ours"
  munge -n | unmunge >/dev/null || die "munge does not work (see /var/log/munge/munged.log)"
}

up() {
  command -v slurmctld >/dev/null || die "slurmctld not found; run 'make setup-slurm'"
  write_conf
  start_munge
  export SLURM_CONF=$CONF
  if ! scontrol ping 2>/dev/null | grep -q UP; then
    slurmctld -f "$CONF"
  fi
  # Under nice: the tasks (children of slurmd's slurmstepd) inherit it and
  # yield to interactive work on a shared machine.
  pgrep -f "slurmd -f $CONF" >/dev/null || nice -n "${SLURM_NICE:-5}" slurmd -f "$CONF"
  local cpus; cpus=$(sed -n 's/^NodeName=.* CPUs=\([0-9]*\).*/\1/p' "$CONF")
  for _ in $(seq 1 60); do
    state=$(sinfo -h -N -o '%t' 2>/dev/null | head -1 || true)
    case "$state" in idle|mix|alloc) echo "slurm: one-node cluster up ($NODE, $cpus of $(nproc) CPUs); SLURM_CONF=$CONF"; return;; esac
    scontrol update nodename="$NODE" state=resume >/dev/null 2>&1 || true
    sleep 1
  done
  die "the node did not become idle in 60 s; see $SLURM_DIR/log/"
}

down() {
  local pids=()
  for f in slurmd slurmctld; do
    [ -f "$SLURM_DIR/$f.pid" ] && pids+=("$(cat "$SLURM_DIR/$f.pid")")
  done
  if [ -f "$SLURM_DIR/munged.ours" ] && [ -f /run/munge/munged.pid ]; then
    pids+=("$(cat /run/munge/munged.pid)")
  fi
  rm -f "$SLURM_DIR/munged.ours"
  [ "${#pids[@]}" -gt 0 ] && kill "${pids[@]}" 2>/dev/null || true
  # slurmd can ignore TERM while it retries a registration: KILL after 10 s.
  local alive=()
  for _ in $(seq 1 10); do
    alive=(); for p in "${pids[@]}"; do kill -0 "$p" 2>/dev/null && alive+=("$p"); done
    [ "${#alive[@]}" -eq 0 ] && break
    sleep 1
  done
  if [ "${#alive[@]}" -gt 0 ]; then kill -9 "${alive[@]}" 2>/dev/null || true; fi
  echo "slurm: stopped"
}

case "${1:-}" in
  up) up ;;
  down) down ;;
  env) echo "export SLURM_CONF=$CONF" ;;
  *) die "usage: $0 up|down|env" ;;
esac
