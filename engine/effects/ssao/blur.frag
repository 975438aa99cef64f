#version 450 core
// Depth-aware (bilateral) blur of the AO buffer, one axis per pass: Gaussian weights times a
// weight that falls off with the relative difference in view depth (the AO buffer's g channel),
// so occlusion does not bleed across silhouettes.
#include "effects/ssao/ssao_data.h"

layout(binding = SSAO_BLUR_IN_UNIT) uniform sampler2D t_ao;  // r AO, g view depth
layout(location = 0) uniform ivec2 u_axis;

layout(location = 0) out vec4 out_ao;

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    ivec2 size = textureSize(t_ao, 0);
    int radius = ssao.blur;
    vec2 centre = texelFetch(t_ao, pixel, 0).rg;
    float z0 = centre.g;
    float sigma = max(float(radius) * 0.5, 0.5);
    float tolerance = 0.02 * abs(z0) + 1e-30;
    float sum = 0.0, weight = 0.0;
    for (int k = -radius; k <= radius; ++k) {
        vec2 s = texelFetch(t_ao, clamp(pixel + u_axis * k, ivec2(0), size - 1), 0).rg;
        float w = exp(-float(k * k) / (2.0 * sigma * sigma) - abs(s.g - z0) / tolerance);
        sum += s.r * w;
        weight += w;
    }
    out_ao = vec4(weight > 0.0 ? sum / weight : centre.r, z0, 0.0, 0.0);
}
