#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# A one-node Slurm on this machine, from Debian's packages (munge, slurmctld, slurmd,
# slurm-client), without systemd: every daemon runs in the foreground under this script's control,
# its state, sockets and logs in STATE_DIR, and is stopped by its PID.
#
#   scripts/slurm-local.sh install          install the packages (root; apt-get), and jq for the test
#   scripts/slurm-local.sh start STATE_DIR  start munged, slurmctld and slurmd; wait for the node
#   scripts/slurm-local.sh stop STATE_DIR   stop them (TERM, then KILL after 10 s)
#
# After `start`, clients need `export SLURM_CONF=STATE_DIR/slurm.conf`. Needs root (the daemons
# run as root: SlurmUser=root). Exits 77 when Slurm cannot be started here (not root, packages
# missing, a daemon does not come up), with the reason on stderr and the daemons' logs.
set -euo pipefail

packages=(munge slurmctld slurmd slurm-client jq)
cannot() {
  echo "slurm-local: cannot start Slurm here: $*" >&2
  exit 77
}

install_packages() {
  [[ $(id -u) -eq 0 ]] || cannot "installing packages needs root"
  local missing=()
  for p in "${packages[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  [[ ${#missing[@]} -eq 0 ]] && return 0
  apt-get update -qq
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}"
}

# Waits up to $2 seconds for the command $1 to succeed.
wait_for() {
  local command=$1 seconds=$2
  for ((i = 0; i < seconds * 5; i++)); do
    if eval "$command" >/dev/null 2>&1; then return 0; fi
    sleep 0.2
  done
  return 1
}

# True if nothing listens on TCP port $1 (and no connection lingers on it).
port_free() {
  ! (exec 3<>"/dev/tcp/127.0.0.1/$1") 2>/dev/null &&
    ! { command -v ss >/dev/null && ss -Htan "( sport = :$1 )" | grep -q .; }
}

show_logs() {
  local state=$1
  for log in "$state"/*.log; do
    [[ -f $log ]] || continue
    echo "--- $log (last 20 lines)" >&2
    tail -n 20 "$log" >&2
  done
}

start() {
  local state=$1
  [[ $(id -u) -eq 0 ]] || cannot "the daemons run as root here (SlurmUser=root) and this is uid $(id -u)"
  for binary in munged slurmctld slurmd sbatch scontrol sinfo; do
    command -v "$binary" >/dev/null || cannot "$binary not found (scripts/slurm-local.sh install)"
  done
  mkdir -p "$state"
  state=$(cd "$state" && pwd)
  chmod 0700 "$state"
  mkdir -p "$state/munge" "$state/ctld" "$state/d"
  chmod 0711 "$state/munge"

  # munge: a key of our own and a socket in STATE_DIR (Slurm is told where, AuthInfo=socket=).
  dd if=/dev/urandom of="$state/munge/munge.key" bs=1024 count=1 status=none
  chmod 0400 "$state/munge/munge.key"
  munged --foreground --force --key-file="$state/munge/munge.key" \
    --socket="$state/munge/munge.socket" --pid-file="$state/munge/munged.pid" \
    --seed-file="$state/munge/munged.seed" --log-file="$state/munged.log" >>"$state/munged.log" 2>&1 &
  echo $! >"$state/munged.pid"
  wait_for "test -S '$state/munge/munge.socket'" 10 || { show_logs "$state"; cannot "munged did not start"; }

  # Ports: SLURM_LOCAL_CTLD_PORT / SLURM_LOCAL_D_PORT, else the first free pair from 16817 (not
  # Slurm's 6817/6818, which a real Slurm on this machine may hold).
  local ctld_port=${SLURM_LOCAL_CTLD_PORT:-} d_port=${SLURM_LOCAL_D_PORT:-}
  if [[ -z $ctld_port ]]; then
    for ((ctld_port = 16817; ctld_port < 16917; ctld_port += 2)); do
      port_free "$ctld_port" && port_free $((ctld_port + 1)) && break
    done
    d_port=$((ctld_port + 1))
  fi
  port_free "$ctld_port" && port_free "$d_port" || cannot "port $ctld_port or $d_port is in use"

  local host node_line cpus memory
  host=$(hostname -s)
  node_line=$(slurmd -C | head -n 1)
  cpus=$(sed -n 's/.* CPUs=\([0-9]*\).*/\1/p' <<<"$node_line")
  memory=$(sed -n 's/.* RealMemory=\([0-9]*\).*/\1/p' <<<"$node_line")
  cat >"$state/slurm.conf" <<CONF
# Written by scripts/slurm-local.sh: one node, everything in $state.
ClusterName=morphmill
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$d_port
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$state/munge/munge.socket
CredType=cred/munge
StateSaveLocation=$state/ctld
SlurmdSpoolDir=$state/d
SlurmctldPidFile=$state/ctld/slurmctld.pid
SlurmdPidFile=$state/d/slurmd.pid
SlurmctldLogFile=$state/slurmctld.log
SlurmdLogFile=$state/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
ReturnToService=2
# Finished jobs stay visible to scontrol for an hour (no accounting database here).
MinJobAge=3600
KillWait=30
MpiDefault=none
NodeName=$host NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=$memory State=UNKNOWN
PartitionName=debug Nodes=ALL Default=YES MaxTime=INFINITE State=UP
CONF
  export SLURM_CONF=$state/slurm.conf

  slurmctld -D -i -f "$SLURM_CONF" >>"$state/slurmctld.stdout" 2>&1 &
  echo $! >"$state/slurmctld.pid"
  wait_for "scontrol ping | grep -q UP" 30 || { show_logs "$state"; cannot "slurmctld did not answer"; }
  slurmd -D -f "$SLURM_CONF" >>"$state/slurmd.stdout" 2>&1 &
  echo $! >"$state/slurmd.pid"
  wait_for "sinfo -h -o %T | grep -qx idle" 60 || {
    sinfo -N -l >&2 || true
    show_logs "$state"
    cannot "the node did not become idle"
  }
  echo "slurm-local: up ($host, $cpus CPUs, ${memory} MiB): export SLURM_CONF=$SLURM_CONF"
}

stop() {
  local state=$1
  local pids=()
  for name in slurmd slurmctld munged; do
    [[ -f $state/$name.pid ]] || continue
    local pid
    pid=$(cat "$state/$name.pid")
    if kill -0 "$pid" 2>/dev/null; then
      kill -TERM "$pid" 2>/dev/null || true
      pids+=("$pid")
    fi
    rm -f "$state/$name.pid"
  done
  for pid in "${pids[@]}"; do
    for ((i = 0; i < 50; i++)); do kill -0 "$pid" 2>/dev/null || break; sleep 0.2; done
    kill -KILL "$pid" 2>/dev/null || true
  done
}

case "${1:-}" in
  install) install_packages ;;
  start) start "${2:?STATE_DIR}" ;;
  stop) stop "${2:?STATE_DIR}" ;;
  *)
    echo "usage: $0 install | start STATE_DIR | stop STATE_DIR" >&2
    exit 2
    ;;
esac
