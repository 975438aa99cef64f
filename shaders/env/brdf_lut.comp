#version 450 core
// The split-sum BRDF LUT (Karis 2013, "Real Shading in Unreal Engine 4"): for the BRDF of
// shaders/common/brdf.glsl (GGX, height-correlated Smith), the directional albedo of the specular
// lobe split into the F0 scale A and the F90 scale B,
//   A + B t = (1/N) sum_h G_vis(l, v) (1 - Fc) and (1/N) sum_h G_vis(l, v) Fc,  Fc = (1 - v.h)^5,
// with h importance-sampled from D(h) (n.h): G_vis = 4 V(l, v) (n.l) (v.h) / (n.h).
// Texel (i, j) holds NdotV = i / (size - 1) and roughness = j / (size - 1), so the end points
// are texel centres (shading.glsl's env_brdf reads it that way).
#include "gpu/bindings.h"
#include "../common/brdf.glsl"
#include "cube.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(rg32f, binding = DST_IMAGE) uniform writeonly image2D lut;
layout(location = 0) uniform int u_size;
layout(location = 1) uniform int u_samples;

void main() {
    ivec2 texel = ivec2(gl_GlobalInvocationID.xy);
    if (texel.x >= u_size || texel.y >= u_size) return;
    float NdotV = max(float(texel.x) / float(u_size - 1), 1e-4);
    float roughness = float(texel.y) / float(u_size - 1);
    float alpha = brdf_alpha(roughness);
    vec3 v = vec3(sqrt(1.0 - NdotV * NdotV), 0.0, NdotV);
    vec2 sum = vec2(0.0);
    for (int i = 0; i < u_samples; ++i) {
        vec3 h = sample_ggx_half(hammersley(uint(i), uint(u_samples)), alpha);
        float VdotH = dot(v, h);
        vec3 l = 2.0 * VdotH * h - v;
        float NdotL = l.z;
        if (NdotL <= 0.0 || VdotH <= 0.0) continue;
        float g = 4.0 * V_SmithGGXCorrelated(NdotL, NdotV, alpha) * NdotL * VdotH / h.z;
        float fc = pow5(1.0 - VdotH);
        sum += vec2((1.0 - fc) * g, fc * g);
    }
    imageStore(lut, texel, vec4(sum / float(u_samples), 0.0, 0.0));
}
