#version 450 core
// One mip level of a GGX-prefiltered cube map (the split sum's first factor, Karis 2013): with
// n = v = r, the NdotL-weighted mean of the radiance over GGX-sampled directions at this level's
// roughness. Filtered importance sampling (Krivanek & Colbert 2008) reads each sample at the mip
// whose texel solid angle matches the sample's, so few samples give a smooth result. Alpha is
// filtered as the colour is (a reflection probe's share of area-light emission: forward.frag).
#include "gpu/bindings.h"
#include "../common/brdf.glsl"
#include "cube.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = SOURCE_UNIT) uniform samplerCubeArray t_source;  // mip 0 plus its box-filtered chain
layout(rgba32f, binding = DST_IMAGE) uniform writeonly imageCubeArray dst;  // this level
layout(location = 0) uniform int u_size;        // face size at this level
layout(location = 1) uniform float u_roughness;
layout(location = 2) uniform int u_samples;
layout(location = 3) uniform int u_source_size; // face size of the source's mip 0

void main() {
    ivec3 id = ivec3(gl_GlobalInvocationID);
    if (id.x >= u_size || id.y >= u_size) return;
    int face = id.z % 6;
    float layer = float(id.z / 6);
    vec3 n = cube_texel_direction(face, id.xy, u_size);
    if (u_roughness <= 0.0) {
        imageStore(dst, id, textureLod(t_source, vec4(n, layer), 0.0));
        return;
    }
    float alpha = brdf_alpha(u_roughness);
    vec3 t, b;
    t = normalize(cross(abs(n.y) < 0.999 ? vec3(0.0, 1.0, 0.0) : vec3(1.0, 0.0, 0.0), n));
    b = cross(n, t);
    float texel_solid_angle = 4.0 * PI / (6.0 * float(u_source_size * u_source_size));
    float max_lod = float(textureQueryLevels(t_source) - 1);
    vec4 sum = vec4(0.0);
    float weight = 0.0;
    for (int i = 0; i < u_samples; ++i) {
        vec3 hl = sample_ggx_half(hammersley(uint(i), uint(u_samples)), alpha);
        vec3 h = t * hl.x + b * hl.y + n * hl.z;
        vec3 l = 2.0 * dot(n, h) * h - n;
        float NdotL = dot(n, l);
        if (NdotL <= 0.0) continue;
        // pdf of l: D(h) (n.h) / (4 v.h) = D(h) / 4 with n = v.
        float pdf = D_GGX(hl.z, alpha) * 0.25;
        float sample_solid_angle = 1.0 / (float(u_samples) * pdf + 1e-6);
        float lod = clamp(0.5 * log2(sample_solid_angle / texel_solid_angle) + 1.0, 0.0, max_lod);
        sum += textureLod(t_source, vec4(l, layer), lod) * NdotL;
        weight += NdotL;
    }
    imageStore(dst, id, weight > 0.0 ? sum / weight : vec4(0.0));
}
