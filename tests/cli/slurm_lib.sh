# Shared by the SLURM tests (sweep_slurm.sh, sweep_slurm_two.sh), sourced
# with `. slurm_lib.sh` from the test's work folder.

skip() { echo "skipped: $*"; exit 77; }

# slurm_test WORKDIR NODES: a fresh work folder (entered; $work its absolute
# path), a cluster of NODES nodes in it (start_slurm) and a trace cache of
# its own.
slurm_test() {
  rm -rf "$1" && mkdir -p "$1" && cd "$1"
  start_slurm "$2"
  export OOVR_CACHE_DIR="$work/cache"
}

# submitted_job LOG: the job id `oovr sweep --backend slurm` printed in LOG
# ("submitted job N: ..."), empty when none.
submitted_job() { sed -n "s/.*submitted job \([0-9][0-9]*\):.*/\1/p" "$1"; }

# release_and_wait JOB: releases a held job, then waits (up to 30 s) until
# squeue no longer lists it.
release_and_wait() {
  scontrol release "$1"
  n=0
  while [ -n "$(squeue -h -j "$1" -o %i 2>/dev/null)" ] && [ $n -lt 150 ]; do sleep 0.2; n=$((n + 1)); done
}

# start_slurm NODES: a SLURM cluster on localhost with NODES nodes, each a
# slurmd of its own (slurmd -N NAME, its own port, spool, pid file and log:
# node-local paths), slurmctld and the nodes on ports of this test only (away
# from a real SLURM's 6817 and 6818), auth/none. Exports SLURM_CONF, sets
# the trap that shuts it down, and waits until every node is idle. Exits 77
# ("skipped", with the reason) when SLURM is not installed or cannot start.
start_slurm() {
  nodes=$1
  for c in slurmctld slurmd sbatch scontrol sinfo squeue sqlite3; do
    command -v $c > /dev/null 2>&1 || skip "$c is not installed (scripts/install-deps.sh --services installs SLURM)"
  done
  work=$(pwd)
  mkdir -p "$work/state"
  host=$(hostname -s)
  cpus=$(nproc)
  [ "$nodes" -gt 1 ] && cpus=1  # one task at a time each, so that the array spreads over the nodes
  base=$((20000 + $$ % 20000))
  names=
  {
    cat <<CONF
ClusterName=oovrtest
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$base
AuthType=auth/none
CredType=cred/none
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
StateSaveLocation=$work/state
SlurmdSpoolDir=$work/spool-%n
SlurmctldPidFile=$work/slurmctld.pid
SlurmdPidFile=$work/slurmd-%n.pid
SlurmctldLogFile=$work/slurmctld.log
SlurmdLogFile=$work/slurmd-%n.log
SlurmUser=$(id -un)
ReturnToService=2
MpiDefault=none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
CONF
    k=1
    while [ $k -le "$nodes" ]; do
      echo "NodeName=node$k NodeHostname=$host NodeAddr=127.0.0.1 Port=$((base + k)) CPUs=$cpus RealMemory=500 State=UNKNOWN"
      k=$((k + 1))
    done
  } > slurm.conf
  k=1
  while [ $k -le "$nodes" ]; do
    names="$names${names:+,}node$k"
    mkdir -p "$work/spool-node$k"
    k=$((k + 1))
  done
  echo "PartitionName=oovr Nodes=$names Default=YES MaxTime=INFINITE State=UP" >> slurm.conf
  export SLURM_CONF="$work/slurm.conf"
  trap stop_slurm EXIT
  slurmctld -c -f "$SLURM_CONF" > ctld.out 2>&1 || skip "slurmctld did not start: $(tail -n 3 ctld.out "$work/slurmctld.log" 2>/dev/null | tr '\n' ' ')"
  k=1
  while [ $k -le "$nodes" ]; do
    slurmd -N "node$k" -f "$SLURM_CONF" > "d$k.out" 2>&1 ||
      skip "slurmd did not start (it needs root here): $(tail -n 3 "d$k.out" "$work/slurmd-node$k.log" 2>/dev/null | tr '\n' ' ')"
    k=$((k + 1))
  done
  tries=0
  until [ "$(sinfo -h -N -o %t 2> /dev/null | grep -c idle)" = "$nodes" ]; do
    tries=$((tries + 1))
    [ $tries -gt 100 ] && skip "the SLURM nodes did not become idle in 20 s: $(sinfo -N 2>&1 | tail -n 2 | tr '\n' ' ')"
    sleep 0.2
  done
}

# Shuts SLURM down and waits (at most 10 s a daemon) until every daemon has gone.
stop_slurm() {
  scontrol shutdown > /dev/null 2>&1 || true
  for f in "$work"/slurmd-*.pid "$work/slurmctld.pid"; do
    [ -f "$f" ] || continue
    pid=$(cat "$f")
    n=0
    while kill -0 "$pid" 2> /dev/null && [ $n -lt 50 ]; do sleep 0.2; n=$((n + 1)); done
    kill -9 "$pid" 2> /dev/null || true
  done
}
