#!/usr/bin/env bash
# Renders a fixed matrix of images (sample scenes x paths x effect settings, the test models,
# the tracer's modes) into OUT_DIR with one `candela batch` process, for checking that a change
# meant to keep behaviour keeps every pixel:
#
#   tests/tools/render_matrix.sh build/bin/candela /tmp/before       # on the old commit
#   tests/tools/render_matrix.sh build/bin/candela /tmp/after        # on the new one
#   tests/tools/render_matrix.sh --compare build/bin/candela /tmp/before /tmp/after
#
# The images are .exr (linear radiance, every bit of the float kept). --compare runs
# `candela compare --tolerance 0` on each pair and exits 1 if any differs or is missing.
set -euo pipefail
here="$(cd "$(dirname "$0")/../.." && pwd)"

if [[ "${1:-}" == "--compare" ]]; then
    candela="$2"; a="$3"; b="$4"; n=0; bad=0
    for f in "$a"/*.exr; do
        name="$(basename "$f")"; n=$((n + 1))
        if [[ ! -f "$b/$name" ]]; then echo "missing: $b/$name"; bad=$((bad + 1)); continue; fi
        if ! "$candela" compare "$f" "$b/$name" --tolerance 0 --check >/dev/null 2>&1; then
            echo "differs: $name"; bad=$((bad + 1))
        fi
    done
    echo "$n images compared, $bad differ or are missing"
    [[ $n -gt 0 && $bad -eq 0 ]]
    exit
fi

candela="$1"; out="$2"
mkdir -p "$out"
jobs="$out/jobs.txt"; : > "$jobs"
size=96x72
scenes="$here/samples/scenes"
models="$here/tests/data/models"
add() { echo "$*" >> "$jobs"; }

for s in cornell_box cornell_point reflections shadow_test spheres transparency; do
    for p in forward deferred; do
        add "$scenes/$s.gltf --size $size --path $p -o $out/${s}_${p}.exr"
        add "$scenes/$s.gltf --size $size --path $p --effects none -o $out/${s}_${p}_none.exr"
        add "$scenes/$s.gltf --size $size --path $p --effects all -o $out/${s}_${p}_all.exr"
        add "$scenes/$s.gltf --size $size --path $p --set aa.mode=msaa --set aa.samples=4 -o $out/${s}_${p}_msaa.exr"
    done
    add "$scenes/$s.gltf --size $size --set shadows.filter=pcss --set ssao.samples=4 --set debug.view=ao -o $out/${s}_knobs.exr"
    add "$scenes/$s.gltf --size $size --set aa.samples=8 --set gi.rays=64 --set rsm.gather=half --set ssao.resolution=half --set arealight.method=pieces --set transparency.mode=peeling -o $out/${s}_knobs2.exr"
    add "$scenes/$s.gltf --size $size --raytrace path --spp 4 --seed 3 -o $out/${s}_path.exr"
    add "$scenes/$s.gltf --size $size --raytrace whitted --spp 2 -o $out/${s}_whitted.exr"
    add "$scenes/$s.gltf --size $size --raytrace ao --spp 2 -o $out/${s}_ao.exr"
done
for d in "$models"/*/; do
    m="$(basename "$d")"
    f="$(ls "$d"*.gltf "$d"*.glb 2>/dev/null | head -n 1 || true)"
    [[ -n "$f" ]] || continue
    add "$f --size $size -o $out/model_${m}.exr"
    add "$f --size $size --path deferred -o $out/model_${m}_deferred.exr"
done
add "generated:random:7 --size $size -o $out/random7.exr"
add "generated:random:7 --size $size --raytrace path --spp 4 -o $out/random7_path.exr"
"$candela" batch "$jobs" --backend egl --quiet
echo "$(ls "$out"/*.exr | wc -l) images in $out"
