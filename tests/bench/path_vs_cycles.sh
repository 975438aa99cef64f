#!/bin/sh
# Whole-process time of `candela render --raytrace path` against Blender Cycles (CPU) on the same
# scene, sample count and size, alternating in one run; prints each run and the medians.
#   tests/bench/path_vs_cycles.sh [ROUNDS] [SPP] [WxH] [SCENE] [NAME=ENV:SHADER_DIR ...]
# Extra candela variants: NAME=ENV:DIR runs `env ENV candela ... --shader-dir DIR` (e.g. the
# one-sample-per-dispatch schedule: "before=CANDELA_RT_SAMPLES_PER_DISPATCH=1:../old/shaders", a checkout of an earlier commit beside this one).
# Needs blender (Debian's 3.4: apt-get install blender python3-numpy) and build/bin/candela.
set -eu
cd "$(dirname "$0")/../.."
rounds=${1:-3}; spp=${2:-64}; size=${3:-256x256}; scene=${4:-samples/scenes/cornell_box.gltf}
shift $(( $# < 4 ? $# : 4 ))
out=${TMPDIR:-/tmp}/path_vs_cycles
mkdir -p "$out"
log="$out/times.txt"
: > "$log"
run() {  # name command...: appends "name wall user+sys"
    name=$1; shift
    /usr/bin/time -f "%e %U %S" -o "$out/t" "$@" > "$out/$name.log" 2>&1
    awk -v n="$name" '{printf "%s %.2f %.2f\n", n, $1, $2 + $3}' "$out/t" | tee -a "$log"
}
for r in $(seq "$rounds"); do
    run cycles blender -b --factory-startup -noaudio -P tests/bench/cycles_cornell.py -- "$scene" "$out/cycles.png" "$spp" "$size"
    grep -h "^cycles: render" "$out/cycles.log" || true
    run candela build/bin/candela render "$scene" --raytrace path --spp "$spp" --size "$size" -o "$out/candela.png" --quiet
    for v in "$@"; do
        name=${v%%=*}; rest=${v#*=}; envs=${rest%%:*}; dir=${rest#*:}
        run "$name" env "$envs" build/bin/candela render "$scene" --raytrace path --spp "$spp" --size "$size" \
            -o "$out/$name.png" --shader-dir "$dir" --quiet
    done
done
echo "medians (wall s, cpu s):"
for name in $(awk '{print $1}' "$log" | sort -u); do
    printf '%s ' "$name"
    awk -v n="$name" '$1 == n {print $2}' "$log" | sort -n | awk '{a[NR]=$1} END {printf "%.2f ", (NR % 2) ? a[(NR+1)/2] : (a[NR/2]+a[NR/2+1])/2}'
    awk -v n="$name" '$1 == n {print $3}' "$log" | sort -n | awk '{a[NR]=$1} END {printf "%.2f\n", (NR % 2) ? a[(NR+1)/2] : (a[NR/2]+a[NR/2+1])/2}'
done
