#!/usr/bin/env bash
# Evaluates --error-budget (docs/error-budget.md) on scenes the model was not fitted on: every
# candidate (and the tracer rung at each budget) measured against --raytrace path on random scenes
# generated:random:1001..(1000+N) and the sample scenes, then the model's choice per scene and budget E = 0.01, 0.03, 0.1 read against
# the measured errors and frame times (what `render --error-budget E --verify` prints, per scene).
#
#   tests/tools/evaluate_error_budget.sh [BUILD_DIR]
#   environment: SEEDS (default 32), SPP (512), SIZE (160x120), JOBS (2), OUT (BUILD_DIR/error-budget),
#                MODEL (a --budget-model JSON; default the built-in model)
# Writes OUT/evaluation.md (the table of docs/error-budget.md) and prints it.
set -euo pipefail
source "$(dirname "$0")/error_budget_common.sh"
seeds=${SEEDS:-32}
scenes=()
for s in $(seq 1001 $((1000 + seeds))); do scenes+=("generated:random:$s"); done
for f in "$root"/samples/scenes/*.gltf; do scenes+=("$f"); done
if [ -z "${SKIP_MEASURE:-}" ]; then
    measure_scenes eval "${scenes[@]}" || echo "evaluate_error_budget.sh: some scenes were not measured (see $out/eval.*.log)" >&2
fi
model=()
[ -n "${MODEL:-}" ] && model=(--budget-model "$MODEL")
csvs=("$out"/eval.*.csv)
"$candela" bench error-budget --evaluate "${csvs[@]}" "${model[@]}" --budgets 0.01,0.03,0.1 --markdown "$out/evaluation.md"
