#version 450 core
// Tracer mode `whitted`.
#include "../trace_common.glsl"
#include "../materials.glsl"
#include "../brdf_sampling.glsl"
#include "../direct_light.glsl"
#ifdef HAS_TRANSMISSION
#include "../dielectric.glsl"
#endif

// Shadow rays: Whitted's transparent shadows. Each crossing of a transmissive surface passes
// (1 - F) * transmission * base colour along a straight line (exact for IOR 1; refraction's
// focusing is what path mode is for). Every opaque surface blocks the light.
vec3 shadow_visibility(Ray ray, float tmax) {
#ifdef HAS_TRANSMISSION
    vec3 T = vec3(1.0);
    for (int crossing = 0; crossing < 16; ++crossing) {
        Hit h = trace_closest(ray, tmax);
        if (h.prim < 0) return T;
        SurfaceHit s = surface_at(ray, h);
        float transmission = material_transmission(s);
        if (transmission <= 0.0) return vec3(0.0);
        BrdfInput m = brdf_input(s);
        bool thin = materials[s.material].thickness <= 0.0;
        float eta = thin ? 1.0 / m.ior : (s.front ? 1.0 / m.ior : m.ior);
        float F = fresnel_dielectric(abs(dot(normalize(ray.dir), s.ng)), eta);
        T *= (1.0 - F) * transmission * m.base_color * volume_transmittance(s, h.t * length(ray.dir));
        if (max(T.r, max(T.g, T.b)) <= 0.0) return vec3(0.0);
        ray.origin = offset_ray(s.p, -s.ng, rt.ray_offset);
        tmax -= h.t;
    }
    return vec3(0.0);
#else
    return opaque_visibility(ray, tmax);
#endif
}

// Whitted (1980): local shading with shadow rays, plus mirror reflection and refraction with the
// exact Fresnel equations, to `max depth`. The branches are kept on a small explicit stack.
// Mirror-only by definition: a rough transmissive surface reflects and refracts here as a smooth
// one (path mode has the rough lobe, dielectric_scatter). Absorption inside solid glass
// (KHR_materials_volume) is applied along refracted rays and transparent shadows, as in path mode.
vec3 radiance(Ray primary, inout Rng rng) {
    const int kMaxStack = 16;
    Ray rays[kMaxStack];
    vec3 weights[kMaxStack];
    int depths[kMaxStack];
    int n = 1;
    rays[0] = primary;
    weights[0] = vec3(1.0);
    depths[0] = 0;
    vec3 sum = vec3(0.0);
    while (n > 0) {
        --n;
        Ray ray = rays[n];
        vec3 w = weights[n];
        int depth = depths[n];
        Hit hit = trace_seen(ray, 3.0e38);
        if (hit.prim < 0) {
            sum += w * environment(ray.dir);
            continue;
        }
        SurfaceHit s = surface_at(ray, hit);
        vec3 v = -normalize(ray.dir);
#ifdef HAS_TRANSMISSION
        w *= volume_transmittance(s, hit.t * length(ray.dir));  // inside solid glass: Beer-Lambert
#endif
#ifdef HAS_BLEND
        // A blended layer on the camera ray: alpha of it, 1 - alpha of what is behind (OVER).
        if (depth == 0) {
            float a = blend_alpha(s);
            if (a < 1.0 && n < kMaxStack) {
                rays[n] = make_ray(offset_ray(s.p, -s.ng, rt.ray_offset), ray.dir);
                weights[n] = w * (1.0 - a);
                depths[n++] = 0;
                w *= a;
            }
        }
#endif
#ifdef MATERIAL_LAYERS
        if (surface_unlit(s)) {
            sum += w * unlit_color(s);
            continue;
        }
#endif
        BrdfInput m = brdf_input(s);
        sum += w * emitted(s);
        bool can_branch = depth < rt.max_depth && n + 2 <= kMaxStack;
#ifdef HAS_TRANSMISSION
        if (material_transmission(s) > 0.0) {
            bool thin = material_thin(s.material);
            float eta = thin ? 1.0 : (s.front ? 1.0 / m.ior : m.ior);
            float F = fresnel_dielectric(dot(v, s.ng), thin ? 1.0 / m.ior : eta);
            if (!can_branch) continue;
            rays[n] = make_ray(offset_ray(s.p, s.ng, rt.ray_offset), reflect(-v, s.ng));
            weights[n] = w * F;
            depths[n++] = depth + 1;
            if (F < 1.0) {
                rays[n] = make_ray(offset_ray(s.p, -s.ng, rt.ray_offset), thin ? -v : refract(-v, s.ng, eta));
                weights[n] = w * (1.0 - F) * m.base_color;
                depths[n++] = depth + 1;
            }
            continue;
        }
#endif
        // Local: punctual and area lights with shadow rays, and the unoccluded environment as an
        // ambient term on the diffuse part.
        sum += w * direct_punctual(s, m, v);
#ifdef HAS_EMITTERS
        sum += w * direct_emitters(s, m, v, rng, false);
#endif
        sum += w * environment(s.ns) * m.base_color * (1.0 - m.metallic);
        if (m.roughness <= rt.whitted_max_roughness && can_branch) {
            // Mirror reflection weighted by the BRDF's Fresnel at normal-vector incidence.
            float cos_v = saturate(dot(v, s.ns));
            vec3 F = mix(F_Schlick(dielectric_f0(m), vec3(dielectric_f90(m)), cos_v),
                         F_Schlick(m.base_color, vec3(1.0), cos_v), m.metallic);
            // The mirror direction about ns, folded above the geometric surface as path mode
            // folds its BRDF (see fold_above).
            rays[n] = make_ray(offset_ray(s.p, s.ng, rt.ray_offset), fold_above(reflect(-v, s.ns), s.ng));
            weights[n] = w * F;
            depths[n++] = depth + 1;
        }
    }
    return sum;
}
