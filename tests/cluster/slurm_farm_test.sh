#!/usr/bin/env bash
# The farm's integration test: `candela farm` on a real single-node Slurm cluster.
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

rm -rf "$WORK"
mkdir -p "$WORK"
WORK=$(readlink -f "$WORK")
FAIL_PREFIX=slurm_farm_test
. "$HERE/slurm_cluster.sh"

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
