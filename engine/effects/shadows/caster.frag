#version 450 core
// Shadow-map pass: depth only; masked materials cut their holes here too.
// CASTER_DEPTH_ONLY (opaque and blended casters): no fragment work at all, so the rasterizer can
// test and write depth early without running a shader (llvmpipe runs every fragment of a shader
// that may discard, then tests depth).
#ifdef CASTER_DEPTH_ONLY
void main() {}
#else
#include "common/scene_data.glsl"
#include "lighting/surface.glsl"

void main() { alpha_test(); }
#endif
