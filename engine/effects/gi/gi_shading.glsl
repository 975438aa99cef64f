// What the GI probes add to the lighting (included by shaders/lighting/shading.glsl through the
// registry): the irradiance of every bounce at a surface point (gi_sample.glsl), reflected by the
// surface (hook indirect_light), and the sky those probes carry (hook carries_sky).
#include "effects/gi/gi_sample.glsl"

// The probes' rays that miss bring the sky: the environment's terms leave it out.
bool gi_carries_sky() {
#ifdef GI_OFF
    return false;
#else
    return gi.on > 0.5;
#endif
}

// Indirect light from the GI probes, reflected as the ambient term reflects the environment
// (split sum): the irradiance E for the Lambert lobe, which keeps what the specular lobe leaves
// it, and E / pi (about the lobe's direction) as the radiance the specular lobe sees, unless a
// reflection source (effect_reflection_source) gives the surroundings (it captured the walls with
// their indirect light already). The layers on top take their share as they do of the ambient
// term: the sheen reflects E (the probes carry the sky's diffuse light, which the ambient term
// then leaves out), and a clear coat passes 1 - F of the light below it (its own reflection is
// the ambient term's).
vec3 gi_indirect_light(BrdfInput bi, vec3 p, vec3 n, vec3 v, vec2 pixel, float occlusion, float transmission) {
#ifdef GI_OFF
    return vec3(0.0);  // no probe data to read yet (gi.on < 0.5: gi.cpp)
#else
    if (gi.on < 0.5) return vec3(0.0);
    vec3 E = gi_irradiance(p, n, v);
    float NdotV = saturate(dot(n, v));
    vec2 ab = env_brdf(bi.roughness, NdotV);
    vec3 specular = vec3(0.0);
    if (effect_reflection_source(p, bi, transmission) < 0) {
        // The radiance the specular lobe sees, as the probes' own trace takes it (probe_trace.comp):
        // E / pi about the lobe's dominant direction (Lagarde & de Rousiers 2014) for a metal,
        // whose lobe is all of its light, E(n) / pi for a dielectric's faint one.
        vec3 Er = E;
        if (bi.metallic > 0.0) {
            float a = bi.roughness * bi.roughness, smooth_ = 1.0 - a;
            Er = gi_irradiance(p, normalize(mix(n, reflect(-v, n), smooth_ * (sqrt(smooth_) + a))), v);
        }
        specular = Er * INV_PI;
    }
#ifdef MATERIAL_LAYERS
    g_ambient_NdotV = NdotV;
    vec3 below = brdf_ambient(bi, NdotV, ab, E, specular, transmission, vec3(0.0));
    vec2 coat_ab = bi.clearcoat > 0.0 ? env_brdf(bi.clearcoat_roughness, saturate(dot(bi.coat_n, v))) : vec2(0.0);
    return occlusion * layers_ambient(bi, n, v, below, E, vec3(0.0), coat_ab);
#else
    return occlusion * brdf_ambient(bi, NdotV, ab, E, specular, transmission, vec3(0.0));
#endif
#endif
}
