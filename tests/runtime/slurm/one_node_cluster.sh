# A one-node Slurm cluster on loopback in a temporary directory, for tests and benchmarks
# (docs/batch.md; sourced by slurm_batch_test.sh and tests/benchmarks/slurm_overhead.sh).
# After sourcing: $T is the directory, SLURM_CONF points at its slurm.conf, the cluster runs
# (slurmctld and slurmd on 127.0.0.1 only, AuthType=auth/none, MaxArraySize=${MAX_ARRAY_SIZE:-4}),
# and an EXIT trap stops both daemons by their pids and removes $T unless $failures > 0.
T=$(mktemp -d /tmp/crackflow-slurm.XXXXXX)
chmod 755 "$T"
export SLURM_CONF=$T/slurm.conf
failures=0
check() {  # check "what" command...
  local what=$1; shift
  if "$@"; then echo "ok: $what"; else echo "FAIL: $what"; failures=$((failures + 1)); fi
}

stop_cluster() {
  squeue -h -o %i 2>/dev/null | xargs -r scancel 2>/dev/null
  scontrol shutdown >/dev/null 2>&1
  for f in "$T/slurmctld.pid" "$T/slurmd.pid"; do
    [ -f "$f" ] || continue
    pid=$(cat "$f")
    for _ in $(seq 100); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
    if kill -0 "$pid" 2>/dev/null; then kill -TERM "$pid"; sleep 1; kill -KILL "$pid" 2>/dev/null; fi
  done
}
cleanup() {
  stop_cluster
  if [ "$failures" -eq 0 ]; then rm -rf "$T"; else echo "kept $T for inspection"; fi
}
trap cleanup EXIT

start_cluster() {
  local ctld_port=$1
  mkdir -p "$T/state" "$T/spool"
  local cpus mem
  cpus=$(nproc)
  mem=$(( $(awk '/MemTotal/ {print $2}' /proc/meminfo) / 1024 * 9 / 10 ))
  cat > "$T/slurm.conf" <<CONF
ClusterName=crackflowtest
SlurmctldHost=localhost(127.0.0.1)
SlurmUser=root
SlurmdUser=root
AuthType=auth/none
CredType=cred/none
CommunicationParameters=NoCtldInAddrAny,NoInAddrAny
SlurmctldPort=$ctld_port
SlurmdPort=$((ctld_port + 1))
StateSaveLocation=$T/state
SlurmdSpoolDir=$T/spool
SlurmctldPidFile=$T/slurmctld.pid
SlurmdPidFile=$T/slurmd.pid
SlurmctldLogFile=$T/slurmctld.log
SlurmdLogFile=$T/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core_Memory
MpiDefault=none
MailProg=/bin/true
ReturnToService=2
SchedulerParameters=sched_interval=1
MaxArraySize=${MAX_ARRAY_SIZE:-4}
NodeName=localhost NodeAddr=127.0.0.1 NodeHostname=localhost CPUs=$cpus RealMemory=$mem
PartitionName=debug Nodes=localhost Default=YES MaxTime=INFINITE State=UP
CONF
  slurmctld -f "$T/slurm.conf" || return 1
  slurmd -f "$T/slurm.conf" -N localhost || return 1
  for _ in $(seq 100); do
    [ "$(sinfo -h -o %T 2>/dev/null)" = idle ] && return 0
    sleep 0.1
  done
  return 1
}

started=0
for attempt in 1 2 3 4 5; do
  port=$(( 20000 + (RANDOM % 20000) * 2 ))
  if start_cluster "$port"; then started=1; break; fi
  echo "cluster did not start on port $port; another try"
  stop_cluster
  rm -rf "$T/state" "$T/spool" "$T"/*.pid
done
if [ "$started" -ne 1 ]; then
  echo "FAIL: the one-node Slurm cluster did not start"; tail -20 "$T"/slurm*.log; failures=1; exit 1
fi
