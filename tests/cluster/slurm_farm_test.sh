#!/usr/bin/env bash
# Issue 25's integration test: `candela farm` on a real single-node Slurm cluster.
#
#   slurm_farm_test.sh CANDELA SCENE WORKDIR
#
# Starts munged, slurmctld and slurmd (Debian's slurm-wlm 22.05 and munge) on localhost with a
# minimal slurm.conf written into a temporary directory, then:
#   1. submits a 4-shard path-traced reference of SCENE through `candela farm reference --submit
#      --wait` and checks that the merged image equals a single-process render of the same seed
#      and spp (to float rounding: the merge sums the shards' means in another order);
#   2. resubmits it with one shard deleted and one truncated: the complete shards are skipped
#      (their logs say so), the broken ones are rendered again, and the result is the same;
#   3. submits a small accuracy sweep (`farm sweep --quick --effect aa --effect ray_tracer_depth`: a raster and a traced section, one task each) and
#      checks that its results.csv equals `bench accuracy` with the same options's up to the
#      timing columns;
#   4. a task that fails (its scene deleted) makes the finishing job fail and name its log.
# Every daemon it started is stopped on exit, also on failure or interruption.
#
# Exit 77 (ctest: skipped) when Slurm or munge is not installed, unless CANDELA_REQUIRE_SLURM=1
# (CI sets it: there a missing Slurm is a failure, not a skip).
set -euo pipefail

CANDELA=$(readlink -f "$1")
SCENE=$(readlink -f "$2")
WORK=$3
HERE=$(cd "$(dirname "$0")" && pwd)

for tool in munged slurmctld slurmd sbatch sinfo scontrol; do
  if ! command -v "$tool" >/dev/null 2>&1 && [ ! -x "/usr/sbin/$tool" ]; then
    echo "slurm_farm_test: $tool is not installed (Debian: slurmctld slurmd slurm-client munge; bash .ci/setup installs them)"
    [ "${CANDELA_REQUIRE_SLURM:-0}" = 1 ] && exit 1
    exit 77
  fi
done
export PATH="$PATH:/usr/sbin"

rm -rf "$WORK"
mkdir -p "$WORK"
WORK=$(readlink -f "$WORK")
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
    echo "--- slurm_farm_test failed (exit $rc); daemon logs:"
    for f in "$RUN"/munged.log "$RUN"/slurmctld.log "$RUN"/slurmd.log; do
      [ -f "$f" ] && { echo "--- $f"; tail -n 30 "$f"; }
    done
  fi
  rm -rf "$RUN"
  exit "$rc"
}
trap stop_all EXIT
trap 'exit 130' INT TERM

fail() { echo "slurm_farm_test: FAIL: $*"; exit 1; }

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
echo "slurm_farm_test: cluster up: $(sinfo -h -N -o '%N %T %c CPUs')"

# --- 1. a 4-shard reference through Slurm against one process ------------------------------
ARGS=(--raytrace path --spp 16 --size 64x64 --seed 5)
t0=$(date +%s.%N)
timeout 600 "$CANDELA" farm reference "$SCENE" -o "$WORK/ref" --shards 4 --batch-stats "${ARGS[@]}" --quiet --submit --wait \
  || fail "the 4-shard reference did not finish (logs in $WORK/ref/logs)"
t1=$(date +%s.%N)
"$CANDELA" render "$SCENE" "${ARGS[@]}" -o "$WORK/single.exr" --quiet
t2=$(date +%s.%N)
"$CANDELA" compare "$WORK/ref/reference.exr" "$WORK/single.exr" --tolerance 1e-5 --max-failing 0 --check \
  || fail "the merged Slurm reference differs from the single-process render"
for i in 0 1 2 3; do
  grep -q "wrote .*shard_000$i.exr (4 samples per pixel)" "$WORK/ref/logs/task_$i.log" || fail "task $i's log does not show its shard"
done
awk -v a="$t0" -v b="$t1" -v c="$t2" 'BEGIN { printf "slurm_farm_test: wall time: 4 shards through Slurm %.1f s (submission to merged image), one process %.1f s\n", b - a, c - b }'

# --- 2. rerun: complete shards are skipped, broken ones rendered again ---------------------
rm "$WORK/ref/shards/shard_0001.exr"
head -c 200 "$WORK/ref/shards/shard_0000.exr" > "$WORK/trunc.exr" && mv "$WORK/trunc.exr" "$WORK/ref/shards/shard_0000.exr"
"$CANDELA" farm status "$WORK/ref" && fail "farm status says a farm with a missing shard is complete"
timeout 600 "$CANDELA" farm submit "$WORK/ref" --wait || fail "the resubmission did not finish"
grep -q "shard_0002.exr is complete (4 samples per pixel): skipped" "$WORK/ref/logs/task_2.log" || fail "task 2 was not skipped on the rerun"
grep -q "shard_0000.exr is not complete" "$WORK/ref/logs/task_0.log" || fail "task 0 did not notice its truncated shard"
grep -q "wrote .*shard_0001.exr" "$WORK/ref/logs/task_1.log" || fail "task 1 did not render its deleted shard again"
"$CANDELA" compare "$WORK/ref/reference.exr" "$WORK/single.exr" --tolerance 1e-5 --max-failing 0 --check \
  || fail "the resumed reference differs from the single-process render"

# --- 3. an accuracy sweep, one section per task ---------------------------------------------
SWEEP=(--quick --effect aa --effect ray_tracer_depth)
timeout 900 "$CANDELA" farm sweep "${SWEEP[@]}" -o "$WORK/sweep" --quiet --submit --wait || fail "the sweep did not finish (logs in $WORK/sweep/logs)"
"$CANDELA" bench accuracy "${SWEEP[@]}" -o "$WORK/accuracy" --quiet
cmake -Wno-dev -DA="$WORK/sweep/results.csv" -DB="$WORK/accuracy/results.csv" -P "$HERE/../cmake/compare_accuracy_csv.cmake" \
  || fail "the farm's results.csv differs from bench accuracy's beyond the timing columns"
[ -s "$WORK/sweep/report.md" ] || fail "the sweep wrote no report"

# --- 4. a failing task: the finishing job fails and names its log ---------------------------
cp "$SCENE" "$WORK/doomed.gltf"
for f in "$(dirname "$SCENE")"/*.bin; do [ -e "$f" ] && cp "$f" "$WORK/"; done
"$CANDELA" farm reference "$WORK/doomed.gltf" -o "$WORK/doomed" --shards 2 --spp 2 --size 16x16 --quiet
rm "$WORK/doomed.gltf"
if timeout 600 "$CANDELA" farm submit "$WORK/doomed" --wait > "$WORK/doomed.out" 2>&1; then fail "a farm whose tasks failed finished with exit 0"; fi
cat "$WORK/doomed.out"
grep -q "logs/task_0.log" "$WORK/doomed/logs/finish.log" || fail "the finishing job does not name the failed task's log"
grep -q "doomed.gltf" "$WORK/doomed/logs/finish.log" || fail "the finishing job does not quote the task's error"

echo "slurm_farm_test: PASS"
