#!/usr/bin/env bash
# What the scheduler costs: a path-traced reference split into shards through a
# single-node Slurm cluster on localhost (tests/cluster/slurm_cluster.sh) against one process of
# the same seed and spp, with the merged image checked against the single one.
#   tests/bench/farm_vs_one.sh CANDELA [SCENE] [SPP] [WxH] [SHARDS]
# Prints both wall times, the tasks' own run times (their logs) and where the rest went: the
# wait from submission to the first task's start and from the last task's end to the merge's
# start (slurmctld's log).
set -euo pipefail
CANDELA=$(readlink -f "$1")
SCENE=$(readlink -f "${2:-$(dirname "$0")/../../samples/scenes/cornell_box.gltf}")
SPP=${3:-256}
SIZE=${4:-256x256}
SHARDS=${5:-4}
HERE=$(cd "$(dirname "$0")" && pwd)
WORK=$(mktemp -d /tmp/candela-farm-bench.XXXXXX)
FAIL_PREFIX=farm_vs_one
. "$HERE/../cluster/slurm_cluster.sh"

ARGS=(--raytrace path --spp "$SPP" --size "$SIZE" --seed 11 --quiet)
"$CANDELA" farm reference "$SCENE" -o "$WORK/ref" --shards "$SHARDS" "${ARGS[@]}" >/dev/null
t0=$(date +%s.%N)
"$CANDELA" farm submit "$WORK/ref" --wait >/dev/null || fail "the farm failed (logs in $WORK/ref/logs)"
t1=$(date +%s.%N)
"$CANDELA" render "$SCENE" "${ARGS[@]}" -o "$WORK/single.exr"
t2=$(date +%s.%N)
"$CANDELA" compare "$WORK/ref/reference.exr" "$WORK/single.exr" --tolerance 1e-5 --max-failing 0 --check >/dev/null \
  || fail "the merged reference differs from the single-process render"
tasks=$(cat "$WORK"/ref/logs/task_*.log | awk '/: exit 0 after/ { s += $(NF - 1) } END { printf "%.1f", s }')
# slurmctld's log: "[2026-12-03T12:08:12.019] sched: Allocate JobId=1_0(2) ..." and
# "[...] _job_complete: JobId=1_3(5) done"; the finishing job is the last allocation.
stamp() { date -d "$(echo "$1" | tr -d '[]')" +%s.%N; }
first_alloc=$(stamp "$(grep -m1 '^\[.*sched: Allocate JobId=' "$RUN/slurmctld.log" | cut -d' ' -f1)")
last_alloc=$(stamp "$(grep '^\[.*sched: Allocate JobId=' "$RUN/slurmctld.log" | tail -n 1 | cut -d' ' -f1)")
last_task_done=$(stamp "$(grep -E '^\[.*_job_complete: JobId=.* done' "$RUN/slurmctld.log" | tail -n 2 | head -n 1 | cut -d' ' -f1)")
waits="$(awk -v s="$t0" -v f="$first_alloc" 'BEGIN { printf "%.1f", f - s }') $(awk -v l="$last_alloc" -v d="$last_task_done" 'BEGIN { printf "%.1f", l - d }')"
echo "farm_vs_one: task starts and ends (slurmctld):"
grep -E '^\[.*(sched: Allocate JobId=|_job_complete: JobId=.* done)' "$RUN/slurmctld.log" | sed 's/^/  /'
read -r queue_wait dep_wait <<< "$waits"
awk -v a="$t0" -v b="$t1" -v c="$t2" -v n="$SHARDS" -v tasks="$tasks" -v q="$queue_wait" -v d="$dep_wait" -v spp="$SPP" -v size="$SIZE" 'BEGIN {
  printf "farm_vs_one: %s spp at %s, %d shards through Slurm: %.1f s from submission to merged image; one process: %.1f s (ratio %.2f)\n", spp, size, n, b - a, c - b, (b - a) / (c - b)
  printf "farm_vs_one: the tasks ran %.1f s in all (sum of their own times); submission to the first task %.1f s; last task to the merge job %.1f s\n", tasks, q, d
}'
rm -rf "$WORK"
