// Lighting of one surface point, shared by the forward pass and the deferred lighting pass (so
// that both compute the same image): the lights of the light buffer and the environment's
// ambient term, plus what the effects add through the hook points. `pixel` seeds per-pixel noise
// (a shadow filter's tap rotation) and addresses screen-space buffers.
#include "../common/brdf.glsl"

// The hook points (render/shading_hooks.hpp): effect_occlusion, effect_light_visibility,
// effect_shaded_light_count, effect_add_direct_light, effect_add_indirect_light,
// effect_reflection_source, effect_reflection_radiance, effect_carries_sky, effect_refraction,
// effect_capture_view. Declared here, defined at the end of this file from the effects that
// provide them (each with a do-nothing default), so this file names no effect.
#include "shading_hooks.glsl"

// Image-based lighting (render/environment.hpp): the static environment as a GGX-prefiltered
// cube (frame.env_mips levels, roughness = level / (levels - 1)), reflection probes captured by
// the env_probe pass and prefiltered the same way, and the split-sum BRDF LUT.
layout(binding = ENV_CUBE_UNIT) uniform samplerCubeArray t_env_cube;  // bound when frame.env_cube_bound = 1
layout(binding = BRDF_LUT_UNIT) uniform sampler2D t_brdf_lut;

// The split sum's second factor: (A, B) with specular albedo = F0 A + F90 B.
vec2 env_brdf(float roughness, float NdotV) {
    vec2 size = vec2(textureSize(t_brdf_lut, 0));
    vec2 uv = (clamp(vec2(NdotV, roughness), 0.0, 1.0) * (size - 1.0) + 0.5) / size;
    return textureLod(t_brdf_lut, uv, 0.0).rg;
}

// Radiance arriving at p from direction r, prefiltered for `roughness`: reflection source k
// (effect_reflection_source), or the static environment when k < 0. `reflected`: r is a
// reflection, whose emitters the direct-light hook adds (effect_reflection_radiance).
vec3 environment_specular(vec3 p, vec3 r, float roughness, int k, bool reflected) {
    if (k >= 0)
        return effect_reflection_radiance(k, p, r, roughness, reflected);
    // Where an effect's indirect light carries the sky, a reflection that no source serves sees
    // that effect's light instead (its indirect-light hook), which holds the sky as the scene lets it in.
    if (reflected && effect_carries_sky()) return vec3(0.0);
    if (frame.env_map_bound < 0.5) return frame.env_radiance.rgb;
    return frame.env_radiance.rgb * textureLod(t_env_cube, vec4(r, 0.0), roughness * float(max(frame.env_mips - 1, 0))).rgb;
}

// The sky's irradiance for the diffuse lobe. Where an effect's indirect light carries it (as
// probes whose missing rays bring the sky, occluded by the scene and bounced), that replaces it.
vec3 environment_irradiance(vec3 n) {
    if (effect_carries_sky()) return vec3(0.0);
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
    return brdf_eval_weighted(bi, n, l, v, 1.0 - transmission) * E * NdotL * effect_light_visibility(light, p, n, l, pixel);
}
vec3 shade_light(int i, BrdfInput bi, vec3 p, vec3 n, vec3 v, vec2 pixel) { return shade_light(i, bi, p, n, v, pixel, 0.0); }

// The solid a transmitted ray crosses (set per draw by the forward pass, render/passes/pass_env.cpp:
// u_volume_shape 1 the box [u_volume_lo, u_volume_hi] in mesh space, 2 the ellipsoid inscribed
// in it, 0 unknown) and its Beer-Lambert coefficient (KHR_materials_volume; forward.frag).
layout(location = 20) uniform int u_volume_shape;
layout(location = 21) uniform vec3 u_volume_lo;
layout(location = 22) uniform vec3 u_volume_hi;
layout(location = 23) uniform mat4 u_volume_to_object;
vec3 g_volume_sigma = vec3(0.0);

// A ray refracted into the solid at p along t (unit) is followed to where it leaves: the exit
// point q, the direction t after the second interface (a totally internally reflected ray is
// followed to the next face, at most three times), and in `weight` what the exit's Fresnel
// and the volume's absorption leave. Unknown shape: unchanged (one interface).
void volume_exit(vec3 p, float ior, inout vec3 t, out vec3 q, inout vec3 weight) {
    q = p;
    if (u_volume_shape == 0) return;
    mat3 to_object = mat3(u_volume_to_object);
    vec3 o = (u_volume_to_object * vec4(p, 1.0)).xyz;
    float f0 = (ior - 1.0) / (ior + 1.0);
    f0 *= f0;
    for (int event = 0; event < 3; ++event) {
        vec3 d = to_object * t;
        float t_exit;
        vec3 n_object;
        if (u_volume_shape == 1) {
            vec3 ds = mix(d, mix(vec3(1e-8), vec3(-1e-8), lessThan(d, vec3(0.0))), lessThan(abs(d), vec3(1e-8)));
            vec3 far_t = max((u_volume_lo - o) / ds, (u_volume_hi - o) / ds);
            t_exit = min(far_t.x, min(far_t.y, far_t.z));
            n_object = far_t.x == t_exit ? vec3(sign(ds.x), 0.0, 0.0) : far_t.y == t_exit ? vec3(0.0, sign(ds.y), 0.0) : vec3(0.0, 0.0, sign(ds.z));
        } else {
            vec3 c = 0.5 * (u_volume_lo + u_volume_hi), r = max(0.5 * (u_volume_hi - u_volume_lo), vec3(1e-8));
            vec3 oo = (o - c) / r, dd = d / r;
            float a = dot(dd, dd), b = dot(oo, dd), cc = dot(oo, oo) - 1.0;
            t_exit = (-b + sqrt(max(b * b - a * cc, 0.0))) / max(a, 1e-20);
            n_object = (oo + t_exit * dd) / r;  // the ellipsoid's gradient
        }
        t_exit = max(t_exit, 0.0);
        q += t * t_exit;  // world and mesh space share the ray parameter
        o += d * t_exit;
        weight *= exp(-g_volume_sigma * t_exit);
        vec3 n_out = normalize(transpose(to_object) * n_object);
        vec3 out_t = refract(t, -n_out, ior);
        if (dot(out_t, out_t) > 1e-12) {
            // Schlick on the outer side of the interface.
            weight *= 1.0 - (f0 + (1.0 - f0) * pow5(1.0 - saturate(dot(out_t, n_out))));
            t = normalize(out_t);
            return;
        }
        t = reflect(t, -n_out);
    }
}

// Environment light reflected towards v (split sum), and for a transmissive surface the light
// refracted through it: one lookup along the direction after the last interface (a thin wall
// does not bend it; a solid of known shape bends it twice, volume_exit).
vec3 shade_ambient(BrdfInput bi, vec3 p, vec3 n, vec3 v, float occlusion, float transmission, bool thin) {
    float NdotV = saturate(dot(n, v));
    vec2 ab = env_brdf(bi.roughness, NdotV);
    int probe = effect_reflection_source(p, bi, transmission);
    vec3 r = reflect(-v, n);
#ifdef MATERIAL_LAYERS
    // Anisotropy: the reflection about a normal bent towards the plane across the direction of
    // anisotropy, the more the rougher along it (the usual bent-normal approximation; the
    // tracer integrates the anisotropic lobe itself).
    if (bi.anisotropy > 0.0) {
        vec3 t, b;
        aniso_frame(bi, n, t, b);
        vec3 across = cross(t, v);
        vec3 an = cross(across, t);
        float bend = 1.0 - bi.anisotropy * (1.0 - bi.roughness);
        bend *= bend;
        bend *= bend;
        vec3 bent = normalize(mix(an, n, bend));
        if (dot(bent, v) > 0.0) r = reflect(-v, bent);
    }
#endif
    vec3 specular = environment_specular(p, r, bi.roughness, probe, true);
    vec3 transmitted = vec3(0.0);
    if (transmission > 0.0) {
        vec3 t = thin ? -v : refract(-v, n, 1.0 / max(bi.ior, 1.0));
        if (dot(t, t) < 1e-12) t = -v;
        t = normalize(t);
        vec3 q = p, weight = vec3(1.0);
        if (!thin) volume_exit(p, max(bi.ior, 1.0), t, q, weight);
        transmitted = weight * environment_specular(q, t, bi.roughness, probe, false);
    }
#ifdef MATERIAL_LAYERS
    g_ambient_NdotV = NdotV;
    vec3 irradiance = environment_irradiance(n);
    vec3 below = brdf_ambient(bi, NdotV, ab, irradiance, specular, transmission, transmitted);
    vec3 coat = vec3(0.0);
    vec2 coat_ab = vec2(0.0);
    if (bi.clearcoat > 0.0) {
        float NcV = saturate(dot(bi.coat_n, v));
        coat_ab = env_brdf(bi.clearcoat_roughness, NcV);
        coat = environment_specular(p, reflect(-v, bi.coat_n), bi.clearcoat_roughness, probe, false);
    }
    return occlusion * layers_ambient(bi, n, v, below, irradiance, coat, coat_ab);
#else
    return occlusion * brdf_ambient(bi, NdotV, ab, environment_irradiance(n), specular, transmission, transmitted);
#endif
}
vec3 shade_ambient(BrdfInput bi, vec3 p, vec3 n, vec3 v, float occlusion) {
    return shade_ambient(bi, p, n, v, occlusion, 0.0, false);
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
        // Visibility is the shadows' answer: a point beyond the light's cutoff (lights.cutoff, an
        // approximation of its energy) is still reached, as the tracer's visibility mode has it.
        light.cutoff = 0.0;
        vec3 l, E;
        float dist;
        light_incidence(light, p, l, E, dist);
        float w = light.color.r + light.color.g + light.color.b;
        weight += w;
        // Reached: facing the light, inside its cone or emitting side, and not shadowed.
        if (dot(n, l) > 0.0 && max(E.r, max(E.g, E.b)) > 0.0) sum += w * effect_light_visibility(light, p, n, l, pixel);
    }
    return weight > 0.0 ? sum / weight : 0.0;
}

// What the effects add to the shading: each registered effect's shading include
// (Effect::shading_include), in registry order, then the hook points defined from them. Both
// generated by the shader library (serve_effect_shading, render/effect_registry.hpp).
#include "effects_shading.glsl"
