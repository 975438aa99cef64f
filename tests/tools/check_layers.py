#!/usr/bin/env python3
"""Checks that engine/'s folders form layers: a file may include headers of its own folder and
of folders in lower layers, never of a higher one, so no two folders depend on each other. And
that the CPU folders (NO_GL) make no GL call: the scene, its loader, images and the shared
block declarations work without a context.

    check_layers.py SOURCE_DIR          exit 0, or 1 naming each offending include

The layers are listed below, lowest first; folders in one layer must not include each other.
A new folder must be added here (an unlisted folder is an error), which is where its place in
the architecture (docs/design.md, "Folders and layers") is decided.
"""
import os
import re
import sys

LAYERS = [
    ["core", "gpu"],         # errors, logging, the cache; GPU data declared once for C++ and GLSL
    ["gl", "image"],         # GL object owners and state; images and their metrics
    ["platform", "profile"], # GL contexts; GPU timers
    ["scene", "shader"],     # the scene and its loader; the shader library
    ["render"],   # the base: GPU scene, frame graph, passes, settings, planning, the renderer,
                  # stills, and the interface effects implement (effect.hpp, effect_registry.hpp)
    ["rt"],       # the ray tracer (reads the GPU scene) and the view-lighting check it serves
    ["effects"],  # the effect modules; registry.cpp defines the registry the base declares
    ["accuracy"], # the accuracy engine (renders references and the effects' knob sweeps)
]
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"')
# Folders whose code runs without a GL context: no gl*() call (comments aside).
NO_GL = {"core", "gpu", "image", "scene"}
GL_CALL = re.compile(r'\bgl[A-Z][A-Za-z0-9]*\s*\(')
STRING = re.compile(r'"(\\.|[^"\\])*"')


def main() -> int:
    root = os.path.join(sys.argv[1] if len(sys.argv) > 1 else ".", "engine")
    layer_of = {f: i for i, names in enumerate(LAYERS) for f in names}
    folders = sorted(d for d in os.listdir(root) if os.path.isdir(os.path.join(root, d)))
    problems = [f"engine/{d}/: not in any layer of tests/tools/check_layers.py" for d in folders if d not in layer_of]
    edges = set()
    for folder in folders:
        for dirpath, _, files in os.walk(os.path.join(root, folder)):
            for name in sorted(files):
                if not name.endswith((".cpp", ".hpp", ".h", ".inc")):
                    continue
                path = os.path.join(dirpath, name)
                with open(path, encoding="utf-8", errors="replace") as f:
                    for number, line in enumerate(f, 1):
                        if folder in NO_GL and GL_CALL.search(STRING.sub('""', line).split("//")[0]):
                            rel = os.path.relpath(path, os.path.dirname(root))
                            problems.append(f"{rel}:{number}: a GL call in engine/{folder}/, which runs without a GL context")
                        m = INCLUDE.match(line)
                        if not m:
                            continue
                        target = m.group(1).split("/")[0]
                        if target == folder or target not in folders:
                            continue
                        edges.add((folder, target))
                        if folder in layer_of and target in layer_of and layer_of[target] >= layer_of[folder]:
                            rel = os.path.relpath(path, os.path.dirname(root))
                            problems.append(f"{rel}:{number}: includes {m.group(1)}: {target}/ is not below {folder}/")
    for p in problems:
        print(p)
    cycles = sorted({tuple(sorted(e)) for e in edges if (e[1], e[0]) in edges})
    for a, b in cycles:
        print(f"back-edge: engine/{a}/ and engine/{b}/ include each other")
    print(f"{len(folders)} folders, {len(edges)} folder dependencies, {len(problems)} problems, {len(cycles)} back-edges")
    return 1 if problems or cycles else 0


if __name__ == "__main__":
    sys.exit(main())
