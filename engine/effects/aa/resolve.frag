#version 450 core
// Anti-aliasing's resolve (engine/effects/aa/aa.cpp): the mean of the pixel's samples in linear
// radiance (a box filter over the pixel, what the tracer's jittered camera rays estimate) and the
// nearest of its depths (reversed-Z: the largest) for the post filters. With sub-frames the
// pass's blend state keeps the running mean over them.
#include "effects/aa/aa_data.h"
#ifdef MULTISAMPLED
layout(binding = AA_HDR_UNIT) uniform sampler2DMS t_hdr;
layout(binding = AA_DEPTH_UNIT) uniform sampler2DMS t_depth;
#else
layout(binding = AA_HDR_UNIT) uniform sampler2D t_hdr;
layout(binding = AA_DEPTH_UNIT) uniform sampler2D t_depth;
#endif
layout(location = 0) out vec4 out_color;

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
#include "effects/aa/aa_data.h"
#ifdef MULTISAMPLED
    int n = textureSamples(t_hdr);
    vec4 sum = vec4(0.0);
    float depth = 0.0;
    for (int i = 0; i < n; ++i) {
        sum += texelFetch(t_hdr, p, i);
        depth = max(depth, texelFetch(t_depth, p, i).r);
    }
    out_color = sum / float(n);
#else
    out_color = texelFetch(t_hdr, p, 0);
    float depth = texelFetch(t_depth, p, 0).r;
#endif
    gl_FragDepth = depth;
}
