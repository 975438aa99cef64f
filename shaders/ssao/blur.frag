#version 450 core
// Depth-aware (bilateral) blur of the AO buffer, one axis per pass: Gaussian weights times a
// weight that falls off with the relative difference in view depth, so occlusion does not bleed
// across silhouettes.
#include "../common/scene_data.glsl"

layout(binding = 0) uniform sampler2D t_ao;
layout(binding = 1) uniform sampler2D t_depth;  // full resolution, reversed-Z
layout(location = 0) uniform ivec2 u_axis;

layout(location = 0) out vec4 out_ao;

float view_depth(ivec2 ao_pixel) {
    ivec2 size = textureSize(t_depth, 0);
    ivec2 full = min(ao_pixel * frame.ssao_mode.z, size - 1);
    float d = texelFetch(t_depth, full, 0).r;
    if (d <= 0.0) return -1e30;
    vec4 p = frame.inv_view_proj * vec4((vec2(full) + 0.5) / vec2(size) * 2.0 - 1.0, d, 1.0);
    return (frame.view * vec4(p.xyz / p.w, 1.0)).z;
}

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    ivec2 size = textureSize(t_ao, 0);
    int radius = frame.ssao_mode.y;
    float z0 = view_depth(pixel);
    float sigma = max(float(radius) * 0.5, 0.5);
    float sum = 0.0, weight = 0.0;
    for (int k = -radius; k <= radius; ++k) {
        ivec2 q = clamp(pixel + u_axis * k, ivec2(0), size - 1);
        float z = view_depth(q);
        float w = exp(-float(k * k) / (2.0 * sigma * sigma)) * exp(-abs(z - z0) / (0.02 * abs(z0) + 1e-30));
        sum += texelFetch(t_ao, q, 0).r * w;
        weight += w;
    }
    out_ao = vec4(weight > 0.0 ? sum / weight : texelFetch(t_ao, pixel, 0).r);
}
