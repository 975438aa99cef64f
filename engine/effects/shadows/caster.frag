#version 450 core
// Shadow-map pass: depth only; masked materials cut their holes here too.
#include "common/scene_data.glsl"
#include "lighting/surface.glsl"

void main() { alpha_test(); }
