#!/usr/bin/env bash
# A one-node Slurm cluster from Debian's slurm-wlm, kept whole in one folder, for testing
# Slurm job submission (job arrays, dependencies) on this machine without touching the system's
# Slurm or munge setup.
#
#   scripts/slurm-cluster.sh start  DIR   # install what is missing, start munged, slurmctld, slurmd
#   scripts/slurm-cluster.sh stop   DIR   # cancel all jobs, stop the daemons, leave nothing running
#   scripts/slurm-cluster.sh status DIR   # which daemons run; sinfo and squeue when they answer
#
# `start` prints the environment the client tools need on stdout (progress goes to stderr):
#   eval "$(scripts/slurm-cluster.sh start DIR)"    # exports SLURM_CONF=DIR/slurm.conf
# The clients (sbatch, squeue, scontrol, scancel, sacct) find the controller's port and the private
# munge socket (AuthInfo=socket=...) in that slurm.conf; nothing else is needed.
#
# Every key, socket, state, spool, log and pid file lives in DIR. The daemons run as root (the
# jobs too). DIR is made traversable by everyone (chmod a+x) because munged refuses a socket whose
# folders are not. Each `start` begins with no jobs (slurmctld -c); a failed `start` stops what it
# started and prints the logs. `stop` is safe to run twice and after a failed start.
# The ports are the first free pair from a base derived from DIR, so clusters in different folders
# can run at once; SLURM_CLUSTER_PORT sets the base. SLURM_CLUSTER_TIMEOUT (seconds, default 60)
# bounds each wait.
set -euo pipefail

timeout_s=${SLURM_CLUSTER_TIMEOUT:-60}

usage() {
  echo "usage: $0 start|stop|status DIR" >&2
  exit 2
}

log() { echo "slurm-cluster: $*" >&2; }

install_missing() {
  local packages=(slurm-wlm munge) missing=() p
  for p in "${packages[@]}"; do
    if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
      missing+=("$p")
    fi
  done
  [ ${#missing[@]} -eq 0 ] && return 0
  log "installing ${missing[*]}"
  local sudo_cmd=()
  if [ "$(id -u)" -ne 0 ]; then sudo_cmd=(sudo); fi
  export DEBIAN_FRONTEND=noninteractive
  "${sudo_cmd[@]}" apt-get update -q >&2
  "${sudo_cmd[@]}" apt-get install -y -q --no-install-recommends "${missing[@]}" >&2
}

# The pid in FILE if that process is alive, is named NAME and belongs to this DIR (its command line
# names DIR or its environment has SLURM_CONF=DIR/slurm.conf), so a recycled pid is never ours.
pid_of() {
  local name=$1 file=$2 pid
  [ -r "$file" ] || return 1
  pid=$(tr -dc '0-9' < "$file")
  [ -n "$pid" ] && owned_by_dir "$pid" "$name" && echo "$pid"
}

owned_by_dir() {
  local pid=$1 name=$2
  [ "$(cat "/proc/$pid/comm" 2>/dev/null)" = "$name" ] || return 1
  tr '\0' '\n' < "/proc/$pid/cmdline" 2>/dev/null | grep -qF "$dir/" && return 0
  tr '\0' '\n' < "/proc/$pid/environ" 2>/dev/null | grep -qxF "SLURM_CONF=$conf"
}

# Step daemons left by this cluster's slurmd, with all their descendants (the jobs).
stray_job_pids() {
  local stepds=() pid
  for pid in $(pgrep -x slurmstepd || true); do
    owned_by_dir "$pid" slurmstepd && stepds+=("$pid")
  done
  [ ${#stepds[@]} -eq 0 ] && return 0
  ps -e -o pid=,ppid= | awk -v roots="${stepds[*]}" '
    BEGIN { n = split(roots, r, " "); for (i = 1; i <= n; i++) mine[r[i]] = 1 }
    { pid[NR] = $1; ppid[NR] = $2 }
    END {
      for (changed = 1; changed; ) {
        changed = 0
        for (i = 1; i <= NR; i++)
          if (!(pid[i] in mine) && (ppid[i] in mine)) { mine[pid[i]] = 1; changed = 1 }
      }
      for (p in mine) print p
    }'
}

# Sends TERM to PIDS, waits up to GRACE seconds until they are gone, then KILLs what is left.
terminate() {
  local grace=$1 deadline alive p
  shift
  local pids=("$@")
  [ ${#pids[@]} -eq 0 ] && return 0
  deadline=$((SECONDS + grace))
  kill -TERM "${pids[@]}" 2>/dev/null || true
  while :; do
    alive=()
    for p in "${pids[@]}"; do kill -0 "$p" 2>/dev/null && alive+=("$p"); done
    [ ${#alive[@]} -eq 0 ] && return 0
    if [ $SECONDS -ge $deadline ]; then
      log "still running after ${grace}s, killing: ${alive[*]}"
      kill -KILL "${alive[@]}" 2>/dev/null || true
      return 0
    fi
    sleep 0.2
  done
}

free_port() {
  ! (exec 3<>"/dev/tcp/127.0.0.1/$1") 2>/dev/null
}

# The first pair of free ports (slurmctld, slurmd) from a base that differs between folders.
pick_ports() {
  local port=${SLURM_CLUSTER_PORT:-$((20000 + 2 * ($(cksum <<< "$dir" | cut -d' ' -f1) % 2000)))}
  local last=$((port + 200))
  while [ "$port" -lt "$last" ]; do
    if free_port "$port" && free_port $((port + 1)); then
      echo "$port $((port + 1))"
      return 0
    fi
    port=$((port + 2))
  done
  log "no free pair of ports in $((last - 200))-$last"
  return 1
}

write_conf() {
  local ctld_port=$1 slurmd_port=$2 node host
  # The node as slurmd itself sees it: NodeName (the host name), CPUs, sockets, cores,
  # threads and RealMemory, so slurmd registers without the node being drained.
  node=$(slurmd -C | head -n 1)
  host=${node#NodeName=}
  host=${host%% *}
  cat > "$conf" <<EOF
# One-node test cluster written by scripts/slurm-cluster.sh; every path is inside $dir.
ClusterName=rigsimtest
SlurmctldHost=$host(127.0.0.1)
SlurmUser=root
SlurmdUser=root
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$dir/munge/munge.socket
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/run/slurmctld.pid
SlurmdPidFile=$dir/run/slurmd.pid
SlurmctldLogFile=$dir/log/slurmctld.log
SlurmdLogFile=$dir/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
# CPUs only: with memory consumable (the default CR_Core_Memory) every job would ask for the
# whole node's memory and the array tasks could not run side by side.
SelectTypeParameters=CR_CPU
MpiDefault=none
SwitchType=switch/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
# No slurmdbd: finished jobs are written here, which \`sacct -c\` reads (without array indices).
JobCompType=jobcomp/filetxt
JobCompLoc=$dir/log/jobcomp.txt
# Finished jobs stay visible to \`scontrol show job\` this long (seconds).
MinJobAge=600
ReturnToService=2
MailProg=/bin/true
$node NodeAddr=127.0.0.1 State=UNKNOWN
PartitionName=debug Nodes=ALL Default=YES MaxTime=INFINITE State=UP
EOF
}

show_logs() {
  local f
  for f in "$dir/munge/munged.log" "$dir/log/slurmctld.log" "$dir/log/slurmd.log"; do
    [ -f "$f" ] || continue
    echo "---- $f (last 30 lines)" >&2
    tail -n 30 "$f" >&2
  done
}

# munged refuses a socket unless every folder above it is searchable by all (o+x).
check_searchable_above() {
  local up=$1
  while [ "$up" != / ]; do
    up=$(dirname "$up")
    [ $((0$(stat -c %a "$up") & 01)) -ne 0 ] ||
      fail_start "munged needs every folder above its socket searchable by all; run: chmod a+x $up"
  done
}

fail_start() {
  log "start failed: $*"
  show_logs
  stop_cluster
  exit 1
}

start_cluster() {
  install_missing
  if pid_of munged "$munged_pid" > /dev/null || pid_of slurmctld "$ctld_pid" > /dev/null ||
     pid_of slurmd "$slurmd_pid" > /dev/null; then
    log "a cluster is already running in $dir; run '$0 stop $dir' first"
    exit 1
  fi
  local t0=$SECONDS ctld_port slurmd_port state
  mkdir -p "$dir"/{munge,state,spool,log,run}
  chmod a+x "$dir"
  chmod 755 "$dir/munge"

  check_searchable_above "$dir"
  [ -f "$dir/munge/munge.key" ] || mungekey --create --keyfile="$dir/munge/munge.key"
  munged --socket="$dir/munge/munge.socket" --key-file="$dir/munge/munge.key" \
    --pid-file="$munged_pid" --log-file="$dir/munge/munged.log" \
    --seed-file="$dir/munge/munged.seed" || fail_start "munged did not start"
  munge -n -S "$dir/munge/munge.socket" | unmunge -S "$dir/munge/munge.socket" > /dev/null ||
    fail_start "munged does not answer on $dir/munge/munge.socket"

  read -r ctld_port slurmd_port <<< "$(pick_ports)"
  [ -n "$slurmd_port" ] || fail_start "no free ports"
  write_conf "$ctld_port" "$slurmd_port"
  export SLURM_CONF=$conf
  slurmctld -c -f "$conf" || fail_start "slurmctld did not start"
  slurmd -f "$conf" || fail_start "slurmd did not start"

  local deadline=$((SECONDS + timeout_s))
  while :; do
    state=$(sinfo -h -N -o '%T' 2> /dev/null || true)
    [ "$state" = idle ] && break
    [ $SECONDS -ge $deadline ] &&
      fail_start "the node is not idle after ${timeout_s}s (sinfo: '${state:-no answer}')"
    sleep 0.2
  done
  log "running in $dir (ports $ctld_port, $slurmd_port), node idle after $((SECONDS - t0))s"
  echo "export SLURM_CONF=$conf"
}

stop_cluster() {
  local pid pids=() job_ids
  # Jobs first, while slurmd is there to end their processes.
  if pid_of slurmctld "$ctld_pid" > /dev/null && pid_of slurmd "$slurmd_pid" > /dev/null; then
    job_ids=$(SLURM_CONF=$conf squeue -h -o '%A' 2> /dev/null || true)
    if [ -n "$job_ids" ]; then
      # shellcheck disable=SC2086
      SLURM_CONF=$conf scancel $job_ids 2> /dev/null || true
      local deadline=$((SECONDS + timeout_s))
      while [ -n "$(SLURM_CONF=$conf squeue -h -o '%A' 2> /dev/null)" ] && [ $SECONDS -lt $deadline ]; do
        sleep 0.2
      done
    fi
  fi
  # All three at once: each takes 1.5-2 s to exit and none needs the others to shut down.
  for pid in $(pid_of slurmd "$slurmd_pid") $(pid_of slurmctld "$ctld_pid") \
             $(pid_of munged "$munged_pid"); do
    pids+=("$pid")
  done
  terminate "$timeout_s" "${pids[@]}"
  # Job processes slurmd did not end: it leaves running steps behind when it stops, e.g. when
  # slurmctld was gone and the jobs could not be cancelled. slurmstepd does not exit on TERM.
  pids=()
  for pid in $(stray_job_pids); do pids+=("$pid"); done
  [ ${#pids[@]} -gt 0 ] && log "ending stray job processes: ${pids[*]}"
  terminate 5 "${pids[@]}"
  rm -f "$ctld_pid" "$slurmd_pid" "$munged_pid"
}

status_cluster() {
  local name file pid all=0
  for name in munged slurmctld slurmd; do
    case $name in
      munged) file=$munged_pid ;;
      slurmctld) file=$ctld_pid ;;
      slurmd) file=$slurmd_pid ;;
    esac
    if pid=$(pid_of "$name" "$file"); then
      echo "$name: running (pid $pid)"
    else
      echo "$name: stopped"
      all=1
    fi
  done
  if [ $all -eq 0 ]; then
    echo "export SLURM_CONF=$conf"
    SLURM_CONF=$conf sinfo || true
    SLURM_CONF=$conf squeue || true
  fi
  return $all
}

[ $# -eq 2 ] || usage
command=$1
dir=$(realpath -m "$2")
conf=$dir/slurm.conf
munged_pid=$dir/munge/munged.pid
ctld_pid=$dir/run/slurmctld.pid
slurmd_pid=$dir/run/slurmd.pid

case $command in
  start) start_cluster ;;
  stop) stop_cluster ;;
  status) status_cluster ;;
  *) usage ;;
esac
