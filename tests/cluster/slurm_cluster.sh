# Sourced by the cluster test and benchmark: starts a single-node Slurm cluster on localhost
# (munged, slurmctld, slurmd; Debian's slurm-wlm 22.05 and munge) with a minimal slurm.conf in a
# temporary directory, exports SLURM_CONF for sbatch/sinfo, and stops every daemon it started
# when the sourcing script exits (also on failure or interruption), printing the daemons' logs
# if it failed. $RUN is that directory ($RUN/slurmctld.log: the scheduler's log).
# Exits 77 (ctest: skipped) when Slurm or munge is not installed, unless CANDELA_REQUIRE_SLURM=1.
for tool in munged slurmctld slurmd sbatch sinfo scontrol; do
  if ! command -v "$tool" >/dev/null 2>&1 && [ ! -x "/usr/sbin/$tool" ]; then
    echo "slurm_cluster: $tool is not installed (Debian: slurmctld slurmd slurm-client munge; bash .ci/setup installs them)"
    [ "${CANDELA_REQUIRE_SLURM:-0}" = 1 ] && exit 1
    exit 77
  fi
done
export PATH="$PATH:/usr/sbin"

# The cluster's own state: sockets, spool, logs, pid files, slurm.conf.
RUN=$(mktemp -d /tmp/candela-slurm.XXXXXX)
chmod 755 "$RUN"
PIDS=()

stop_all() {
  local rc=$?
  for pid in "${PIDS[@]}"; do kill "$pid" 2>/dev/null || true; done
  for pid in "${PIDS[@]}"; do
    for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
    kill -9 "$pid" 2>/dev/null || true
  done
  if [ "$rc" -ne 0 ]; then
    echo "--- ${FAIL_PREFIX:-slurm_cluster} failed (exit $rc); daemon logs:"
    for f in "$RUN"/munged.log "$RUN"/slurmctld.log "$RUN"/slurmd.log; do
      [ -f "$f" ] && { echo "--- $f"; tail -n 30 "$f"; }
    done
  fi
  rm -rf "$RUN"
  exit "$rc"
}
trap stop_all EXIT
trap 'exit 130' INT TERM

fail() { echo "${FAIL_PREFIX:-slurm_cluster}: FAIL: $*"; exit 1; }

# Waits up to $1 seconds for the command after it to succeed.
wait_for() {
  local limit=$1
  shift
  for _ in $(seq $((limit * 5))); do
    "$@" >/dev/null 2>&1 && return 0
    sleep 0.2
  done
  return 1
}

free_port() {
  local p
  for _ in $(seq 100); do
    p=$((20000 + RANDOM % 30000))
    if ! (exec 3<>"/dev/tcp/127.0.0.1/$p") 2>/dev/null; then echo "$p"; return; fi
  done
  fail "no free TCP port"
}

# --- munge: a fresh key and its own socket ------------------------------------------------
mkdir -m 700 "$RUN/munge"
dd if=/dev/urandom of="$RUN/munge/munge.key" bs=1024 count=1 status=none
chmod 400 "$RUN/munge/munge.key"
SOCKET="$RUN/munge/munge.socket"
munged --force --key-file="$RUN/munge/munge.key" --socket="$SOCKET" --pid-file="$RUN/munge/munged.pid" \
  --log-file="$RUN/munged.log" --seed-file="$RUN/munge/munged.seed"
wait_for 10 test -f "$RUN/munge/munged.pid" || fail "munged did not start"
PIDS+=("$(cat "$RUN/munge/munged.pid")")
munge -n -S "$SOCKET" | unmunge -S "$SOCKET" >/dev/null || fail "munge cannot encode/decode a credential"

# --- slurm.conf: one node (this host, its CPUs and memory from slurmd -C), one partition -----
USER_NAME=$(id -un)
NODE=$(hostname -s)
NODE_LINE=$(slurmd -C | head -n 1)
mkdir -p "$RUN/spool/ctld" "$RUN/spool/d"
cat > "$RUN/slurm.conf" <<EOF
ClusterName=candela-test
SlurmctldHost=$NODE(127.0.0.1)
SlurmctldPort=$(free_port)
SlurmdPort=$(free_port)
SlurmUser=$USER_NAME
SlurmdUser=$USER_NAME
AuthType=auth/munge
AuthInfo=socket=$SOCKET
CredType=cred/munge
StateSaveLocation=$RUN/spool/ctld
SlurmdSpoolDir=$RUN/spool/d
SlurmctldPidFile=$RUN/slurmctld.pid
SlurmdPidFile=$RUN/slurmd.pid
SlurmctldLogFile=$RUN/slurmctld.log
SlurmdLogFile=$RUN/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
MpiDefault=none
ReturnToService=2
SlurmdTimeout=60
InactiveLimit=0
KillWait=5
$NODE_LINE NodeAddr=127.0.0.1 State=UNKNOWN
PartitionName=test Nodes=$NODE Default=YES MaxTime=INFINITE State=UP
EOF
sed -i 's/ UpTime=.*//' "$RUN/slurm.conf"
export SLURM_CONF="$RUN/slurm.conf"

slurmctld -D -c -f "$SLURM_CONF" >>"$RUN/slurmctld.log" 2>&1 &
PIDS+=($!)
wait_for 30 scontrol ping || fail "slurmctld did not answer"
slurmd -D -f "$SLURM_CONF" -N "$NODE" >>"$RUN/slurmd.log" 2>&1 &
PIDS+=($!)
node_ready() { sinfo -h -N -o '%T' | grep -Eq '^(idle|mixed|allocated)'; }
wait_for 60 node_ready || fail "the node did not become idle: $(sinfo -N 2>&1)"
echo "slurm_cluster: up: $(sinfo -h -N -o '%N %T %c CPUs')"

