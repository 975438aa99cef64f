// Lighting of one surface point, shared by the forward pass and the deferred lighting pass (so
// that both compute the same image): punctual lights and area-light pieces with their shadows,
// plus the environment's ambient term. `pixel` seeds the shadow filter's tap rotation.
#include "../common/brdf.glsl"
#include "shadows.glsl"

layout(binding = 5) uniform sampler2D t_environment;
layout(binding = 9) uniform sampler2D t_ssao;  // bound when frame.ssao_mode.x = 1

// Screen-space ambient occlusion at a pixel (1 without the SSAO pass). It scales ambient and
// environment light only, never direct light.
float ssao_at(vec2 pixel) {
    if (frame.ssao_mode.x == 0) return 1.0;
    // AO texel i was computed at full-resolution pixel i * f (centre i * f + 0.5).
    float f = float(frame.ssao_mode.z);
    return texture(t_ssao, ((pixel - 0.5) / f + 0.5) / vec2(textureSize(t_ssao, 0))).r;
}

layout(binding = 10) uniform sampler2D t_rsm_indirect;  // bound when frame.rsm_mode.x = 1
// One-bounce diffuse light from the reflective shadow maps, reflected by the Lambert part. A
// gather at lower resolution is upsampled geometry-aware: the four nearest gather samples
// weighted bilinearly and by how close their view depth (alpha) is to this pixel's, so light
// does not leak across silhouettes (joint bilateral upsampling, Kopf et al. 2007).
vec3 rsm_indirect(BrdfInput bi, vec2 pixel, vec3 p) {
    if (frame.rsm_mode.x == 0) return vec3(0.0);
    int f = max(frame.rsm_mode.y, 1);
    vec3 E;
    if (f == 1) {
        E = texelFetch(t_rsm_indirect, ivec2(pixel), 0).rgb;
    } else {
        // Gather sample i was computed at full-resolution pixel i * f (centre i * f + 0.5).
        float z = (frame.view * vec4(p, 1.0)).z;
        vec2 lo = (pixel - 0.5) / float(f);
        ivec2 base = ivec2(floor(lo));
        vec2 t = lo - vec2(base);
        ivec2 size = textureSize(t_rsm_indirect, 0);
        vec3 sum = vec3(0.0);
        float wsum = 0.0;
        for (int j = 0; j < 2; ++j)
            for (int i = 0; i < 2; ++i) {
                vec4 s = texelFetch(t_rsm_indirect, clamp(base + ivec2(i, j), ivec2(0), size - 1), 0);
                float wb = (i == 0 ? 1.0 - t.x : t.x) * (j == 0 ? 1.0 - t.y : t.y);
                float w = wb / (1e-3 + abs(s.a - z) / max(abs(z), 1e-30));
                sum += s.rgb * w;
                wsum += w;
            }
        E = wsum > 0.0 ? sum / wsum : vec3(0.0);
    }
    return bi.base_color * (1.0 - bi.metallic) * INV_PI * E;
}

vec3 environment_specular(vec3 r, float roughness) {
    if (frame.env_radiance.w < 0.5) return frame.env_radiance.rgb;
    float lod = roughness * float(max(frame.counts.y - 1, 0));
    return frame.env_radiance.rgb * textureLod(t_environment, direction_to_equirect(r), lod).rgb;
}

vec3 environment_irradiance(vec3 n) {
    if (frame.env_radiance.w < 0.5) return PI * frame.env_radiance.rgb;
    return max(sh_irradiance(n), vec3(0.0));
}

// Light i reflected towards v.
vec3 shade_light(int i, BrdfInput bi, vec3 p, vec3 n, vec3 v, vec2 pixel) {
    PunctualLight light = lights[i];
    vec3 l, E;
    float dist;
    light_incidence(light, p, l, E, dist);
    float NdotL = dot(n, l);
    if (NdotL <= 0.0 || max(E.r, max(E.g, E.b)) <= 0.0) return vec3(0.0);
    return brdf_eval(bi, n, l, v) * E * NdotL * shadow_factor(light, p, n, l, pixel);
}

vec3 shade_ambient(BrdfInput bi, vec3 n, vec3 v, float occlusion) {
    vec3 r = reflect(-v, n);
    return occlusion * brdf_ambient(bi, n, v, environment_irradiance(n), environment_specular(r, bi.roughness));
}

// The debug view `visibility` (debug.view): the fraction of light frame.debug.y that reaches p
// (0 where the surface faces away or the light sends nothing towards p: outside a spot's cone,
// behind a one-sided emitter). Light indices below the punctual count are punctual lights;
// any larger index stands for all area-light pieces together, weighted by their power.
float light_visibility(vec3 p, vec3 n, vec2 pixel) {
    int first = frame.debug.y, last = frame.debug.y;
    if (frame.debug.y >= frame.counts.z) {
        first = frame.counts.z;
        last = frame.counts.x - 1;
    }
    float sum = 0.0, weight = 0.0;
    for (int i = first; i <= last; ++i) {
        PunctualLight light = lights[i];
        vec3 l, E;
        float dist;
        light_incidence(light, p, l, E, dist);
        float w = light.color.r + light.color.g + light.color.b;
        weight += w;
        // Reached: facing the light, inside its cone or emitting side, and not shadowed.
        if (dot(n, l) > 0.0 && max(E.r, max(E.g, E.b)) > 0.0) sum += w * shadow_factor(light, p, n, l, pixel);
    }
    return weight > 0.0 ? sum / weight : 0.0;
}
