# Shared by fit_error_budget.sh and evaluate_error_budget.sh (sourced, not run): the settings from
# the environment and the measurement of every candidate of the --error-budget ladder on scenes.
#   SPP (path reference, default 512), SIZE (160x120), JOBS (processes, default 2),
#   OUT (measurements, default BUILD_DIR/error-budget), CANDELA (default BUILD_DIR/bin/candela),
#   TRACE_BUDGETS (the budgets at which the tracer rung is measured, default 0.01,0.03,0.1; none)
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
build=${1:-$root/build}
candela=${CANDELA:-$build/bin/candela}
spp=${SPP:-512}
size=${SIZE:-160x120}
jobs=${JOBS:-2}
out=${OUT:-$build/error-budget}
trace_budgets=${TRACE_BUDGETS:-0.01,0.03,0.1}
mkdir -p "$out"

# measure_scenes PREFIX SCENE...: JOBS processes, each a share of the scenes into its own
# OUT/PREFIX.J.csv (one GL context and program cache each). Returns 1 if a process failed (its
# log is OUT/PREFIX.J.log); the scenes it did measure stay in its CSV.
measure_scenes() {
    local prefix=$1
    shift
    local scenes=("$@") pids=() status=0 j i
    for j in $(seq 0 $((jobs - 1))); do
        local part=()
        for i in "${!scenes[@]}"; do (( i % jobs == j )) && part+=("${scenes[$i]}"); done
        rm -f "$out/$prefix.$j.csv"
        "$candela" bench error-budget "${part[@]}" --csv "$out/$prefix.$j.csv" --size "$size" --spp "$spp" --trace-budgets "$trace_budgets" --quiet \
            > "$out/$prefix.$j.log" 2>&1 &
        pids+=($!)
    done
    for i in "${pids[@]}"; do wait "$i" || status=1; done
    return $status
}
