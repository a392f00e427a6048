# A single-node Slurm cluster in a temporary directory, for the farm test: munged and
# slurmctld and slurmd on localhost with a generated key and slurm.conf, nothing of the
# machine's own configuration read or changed (packages in a chroot start no daemons).
# Sourced; needs root. start_cluster DIR starts it and exports SLURM_CONF; stop_cluster
# stops what it started (call it from a trap).

# A port on localhost that nothing listens on: a connection to it is refused. (Bash alone:
# the chroot CI runs in has no python.)
free_port() {
  local port
  while :; do
    port=$((20000 + RANDOM % 40000))
    if ! (exec 3<>"/dev/tcp/127.0.0.1/$port") 2>/dev/null; then
      echo "$port"
      return
    fi
  done
}

start_cluster() {
  local dir=$1
  mkdir -p "$dir/state" "$dir/spool" "$dir/munge"
  chmod 0700 "$dir/munge"
  # munged: its own key, socket, pid and log here; --force lets it run as root in a
  # directory it did not make.
  dd if=/dev/urandom of="$dir/munge/munge.key" bs=1024 count=1 status=none
  chmod 0400 "$dir/munge/munge.key"
  munged --force --key-file="$dir/munge/munge.key" --socket="$dir/munge/munge.sock" \
    --pid-file="$dir/munge/munged.pid" --log-file="$dir/munge/munged.log" \
    --seed-file="$dir/munge/munged.seed" || { cat "$dir/munge/munged.log" >&2; return 1; }

  local cpus mem ctld_port slurmd_port host
  # The node and the controller are named after this machine, with their address given, so
  # that nothing needs a name looked up: a chroot may have no /etc/hosts, and then even
  # "localhost" goes to DNS, which can hang every daemon and client for minutes.
  host=$(hostname -s 2>/dev/null || cat /proc/sys/kernel/hostname)
  cpus=$(nproc)
  mem=$(( $(awk '/^MemTotal/ {print $2}' /proc/meminfo) / 1024 / 2 ))
  ctld_port=$(free_port)
  slurmd_port=$(free_port)
  while [[ $slurmd_port == "$ctld_port" ]]; do slurmd_port=$(free_port); done
  cat >"$dir/slurm.conf" <<CONF
ClusterName=moirefarm
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$dir/munge/munge.sock
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/slurmctld.log
SlurmdLogFile=$dir/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SchedulerType=sched/builtin
SchedulerParameters=sched_interval=1,sched_min_interval=100000
MailProg=/bin/true
MpiDefault=none
ReturnToService=2
MinJobAge=300
NodeName=$host NodeAddr=127.0.0.1 NodeHostname=$host CPUs=$cpus RealMemory=$mem State=UNKNOWN
PartitionName=farm Nodes=$host Default=YES MaxTime=INFINITE State=UP
CONF
  export SLURM_CONF=$dir/slurm.conf
  slurmctld -D -i >"$dir/slurmctld.out" 2>&1 &
  echo $! >"$dir/slurmctld.job"
  slurmd -D -N "$host" >"$dir/slurmd.out" 2>&1 &
  echo $! >"$dir/slurmd.job"
  # Up when the node takes jobs.
  local i
  for i in $(seq 1 100); do
    if timeout 5 sinfo -h -N -o '%T' 2>/dev/null | grep -qE '^(idle|mixed|allocated)'; then return 0; fi
    sleep 0.2
  done
  echo "the test cluster did not come up; its logs:" >&2
  tail -n 20 "$dir"/slurmctld.log "$dir"/slurmd.log "$dir"/*.out >&2 || true
  return 1
}

stop_cluster() {
  local dir=$1 f
  # Jobs still running (a test that failed half way) are this cluster's: SLURM_CONF names it.
  [[ -n "${SLURM_CONF:-}" ]] && timeout 10 scancel --quiet --user="$(id -un)" 2>/dev/null || true
  for f in slurmd slurmctld; do
    [[ -f "$dir/$f.job" ]] && kill "$(cat "$dir/$f.job")" 2>/dev/null || true
  done
  for f in slurmd slurmctld; do
    [[ -f "$dir/$f.job" ]] && wait "$(cat "$dir/$f.job")" 2>/dev/null || true
  done
  if [[ -f "$dir/munge/munged.pid" ]]; then
    local pid i
    pid=$(cat "$dir/munge/munged.pid")
    kill "$pid" 2>/dev/null || true
    # Not our child, so not waited for: watched until gone (it writes its seed on the way).
    for i in $(seq 1 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
  fi
}
