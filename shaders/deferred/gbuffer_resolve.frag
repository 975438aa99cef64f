#version 450 core
// Multisampled G-buffer (anti-aliasing, engine/render/passes/gbuffer.cpp): sample 0's depth and
// octahedral normal into the single-sample depth and normals the screen-space effects read.
// One sample, not a mean: depth and normal then come from the same surface.
#include "gpu/bindings.h"
layout(binding = RESOLVE_DEPTH_UNIT) uniform sampler2DMS g_depth;
layout(binding = RESOLVE_NORMAL_UNIT) uniform sampler2DMS g_normal_rm;
layout(location = 0) out vec2 out_normal;

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    out_normal = texelFetch(g_normal_rm, p, 0).xy;
    gl_FragDepth = texelFetch(g_depth, p, 0).r;
}
