#version 450 core
// The forward path's depth prepass (forward.depth_prepass): depth only, so the shading pass after
// it runs each visible pixel once.
// DEPTH_ONLY (the "depth_prepass" program, for draws that are not alpha-masked): no fragment work
// at all, so the rasterizer can test and write depth without running a shader (llvmpipe runs
// every fragment of a shader that may discard, or of a full shading program with colour writes
// off, before it tests depth). Otherwise ("depth_prepass_mask") the alpha test cuts the holes of
// MASK materials, as the shading pass does.
#ifdef DEPTH_ONLY
void main() {}
#else
#include "../common/scene_data.glsl"
#include "../lighting/surface.glsl"

void main() { alpha_test(); }
#endif
