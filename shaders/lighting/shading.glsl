// Lighting of one surface point, shared by the forward pass and the deferred lighting pass (so
// that both compute the same image): punctual lights and area-light pieces with their shadows,
// plus the environment's ambient term and the indirect light (RSM, GI probes). `pixel` seeds the shadow filter's tap rotation.
#include "../common/brdf.glsl"
#include "effects/shadows/shadows_shading.glsl"
#include "effects/ssao/ssao_shading.glsl"

#include "effects/rsm/rsm_shading.glsl"
#include "effects/gi/gi_shading.glsl"
#include "effects/area_lights/area_lights_shading.glsl"

// Image-based lighting (render/environment.hpp): the static environment as a GGX-prefiltered
// cube (frame.env_mips levels, roughness = level / (levels - 1)), reflection probes captured by
// the env_probe pass and prefiltered the same way, and the split-sum BRDF LUT.
layout(binding = ENV_CUBE_UNIT) uniform samplerCubeArray t_env_cube;  // bound when frame.env_cube_bound = 1
layout(binding = BRDF_LUT_UNIT) uniform sampler2D t_brdf_lut;
#include "effects/reflections/reflections_shading.glsl"

// The split sum's second factor: (A, B) with specular albedo = F0 A + F90 B.
vec2 env_brdf(float roughness, float NdotV) {
    vec2 size = vec2(textureSize(t_brdf_lut, 0));
    vec2 uv = (clamp(vec2(NdotV, roughness), 0.0, 1.0) * (size - 1.0) + 0.5) / size;
    return textureLod(t_brdf_lut, uv, 0.0).rg;
}

// Radiance arriving at p from direction r, prefiltered for `roughness`: probe k (probe_at), or
// the static environment when k < 0.
vec3 environment_specular(vec3 p, vec3 r, float roughness, int k) {
    if (k >= 0)
        return probe_radiance(k, p, r, roughness);
    if (frame.env_map_bound < 0.5) return frame.env_radiance.rgb;
    return frame.env_radiance.rgb * textureLod(t_env_cube, vec4(r, 0.0), roughness * float(max(frame.env_mips - 1, 0))).rgb;
}

vec3 environment_irradiance(vec3 n) {
    if (frame.env_map_bound < 0.5) return PI * frame.env_radiance.rgb;
    return max(sh_irradiance(n), vec3(0.0));
}

// Light i reflected towards v. A transmissive surface (KHR_materials_transmission) keeps its
// specular lobe and trades `transmission` of its diffuse lobe for transmitted light.
vec3 shade_light(int i, BrdfInput bi, vec3 p, vec3 n, vec3 v, vec2 pixel, float transmission) {
    LightData light = lights[i];
    vec3 l, E;
    float dist;
    light_incidence(light, p, l, E, dist);
    float NdotL = dot(n, l);
    if (NdotL <= 0.0 || max(E.r, max(E.g, E.b)) <= 0.0) return vec3(0.0);
    return brdf_eval_weighted(bi, n, l, v, 1.0 - transmission) * E * NdotL * shadow_factor(light, p, n, l, pixel);
}
vec3 shade_light(int i, BrdfInput bi, vec3 p, vec3 n, vec3 v, vec2 pixel) { return shade_light(i, bi, p, n, v, pixel, 0.0); }

// Environment light reflected towards v (split sum), and for a transmissive surface the light
// refracted through it: one lookup along the direction after the first interface (a thin wall
// does not bend it), the seeds' "first direction change only".
vec3 shade_ambient(BrdfInput bi, vec3 p, vec3 n, vec3 v, float occlusion, float transmission, bool thin) {
    float NdotV = saturate(dot(n, v));
    vec2 ab = env_brdf(bi.roughness, NdotV);
#ifdef FORWARD_NO_PROBES
    int probe = -1;  // probe_at's answer with reflections.probes 0 (forward/forward.frag)
#else
    int probe = probe_at(p, bi, transmission);
#endif
    vec3 specular = environment_specular(p, reflect(-v, n), bi.roughness, probe);
    vec3 transmitted = vec3(0.0);
    if (transmission > 0.0) {
        vec3 t = thin ? -v : refract(-v, n, 1.0 / max(bi.ior, 1.0));
        if (dot(t, t) < 1e-12) t = -v;
        transmitted = environment_specular(p, normalize(t), bi.roughness, probe);
    }
    return occlusion * brdf_ambient(bi, ab, environment_irradiance(n), specular, transmission, transmitted);
}
vec3 shade_ambient(BrdfInput bi, vec3 p, vec3 n, vec3 v, float occlusion) {
    return shade_ambient(bi, p, n, v, occlusion, 0.0, false);
}

// Indirect light from the GI probes (effects/gi), reflected as the ambient term reflects the
// environment (split sum): the irradiance E for the Lambert lobe, which keeps what the specular
// lobe leaves it, and E / pi as the radiance the specular lobe sees, unless a reflection probe
// gives the surroundings (it captured the walls with their indirect light already).
vec3 shade_gi(BrdfInput bi, vec3 p, vec3 n, vec3 v, float occlusion, float transmission) {
    if (gi.on < 0.5) return vec3(0.0);
    vec3 E = gi_irradiance(p, n, v);
    vec2 ab = env_brdf(bi.roughness, saturate(dot(n, v)));
    vec3 specular = probe_at(p, bi, transmission) >= 0 ? vec3(0.0) : E * INV_PI;
    return occlusion * brdf_ambient(bi, ab, E, specular, transmission, vec3(0.0));
}

// The debug view `visibility` (debug.view): the fraction of light frame.debug_light that reaches p
// (0 where the surface faces away or the light sends nothing towards p: outside a spot's cone,
// behind a one-sided emitter). Light indices below the punctual count are punctual lights;
// any larger index stands for all area-light pieces together, weighted by their power.
float light_visibility(vec3 p, vec3 n, vec2 pixel) {
    int first = frame.debug_light, last = frame.debug_light;
    if (frame.debug_light >= frame.punctual_light_count) {
        first = frame.punctual_light_count;
        last = frame.light_count - 1;
    }
    float sum = 0.0, weight = 0.0;
    for (int i = first; i <= last; ++i) {
        LightData light = lights[i];
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
