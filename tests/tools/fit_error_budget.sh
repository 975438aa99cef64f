#!/usr/bin/env bash
# Refits the model behind --error-budget (docs/error-budget.md): measures every candidate of the
# ladder on the fitting scenes (random scenes generated:random:1..N and the sample scenes) against
# --raytrace path, then fits and writes engine/accuracy/error_budget_model.inc (rebuild after).
#
#   tests/tools/fit_error_budget.sh [BUILD_DIR]
#   environment: SEEDS (default 48: seeds 1..48), SPP (path reference, default 512), SIZE (160x120),
#                JOBS (processes, default 2), OUT (measurements, default BUILD_DIR/error-budget)
# The evaluation uses other seeds (tests/tools/evaluate_error_budget.sh): keep them apart.
set -euo pipefail
source "$(dirname "$0")/error_budget_common.sh"
seeds=${SEEDS:-48}
scenes=()
for s in $(seq 1 "$seeds"); do scenes+=("generated:random:$s"); done
for f in "$root"/samples/scenes/*.gltf; do scenes+=("$f"); done
trace_budgets=none  # the tracer rung has no model to fit: it measures its own noise while it renders
measure_scenes fit "${scenes[@]}" || echo "fit_error_budget.sh: some scenes were not measured (see $out/fit.*.log)" >&2
csvs=("$out"/fit.*.csv)
"$candela" bench error-budget --fit "${csvs[@]}" --size "$size" --spp "$spp" -o "$root/engine/accuracy/error_budget_model.inc"
"$candela" bench error-budget --fit "${csvs[@]}" --size "$size" --spp "$spp" -o "$out/model.json" > /dev/null
