#version 450 core
// Tracer modes `path` and `direct` (path with one bounce, rt.params.x = 1).
#include "../trace_common.glsl"
#include "../materials.glsl"
#include "../brdf_sampling.glsl"
#include "../env_sampling.glsl"
#include "../direct_light.glsl"

// Shadow rays: every surface blocks the light (transmissive ones too; refraction is sampled).
vec3 shadow_visibility(Ray ray, float tmax) { return opaque_visibility(ray, tmax); }

// Unidirectional path tracing with next-event estimation (punctual lights always, emissive
// triangles with MIS against BRDF sampling), Russian roulette after three bounces.
vec3 radiance(Ray ray, inout Rng rng) {
    vec3 sum = vec3(0.0);
    vec3 throughput = vec3(1.0);
    float last_brdf_pdf = 0.0;  // 0: the last bounce was specular-delta or the camera
    int max_depth = rt.params.x;
#ifdef HAS_BLEND
    int layers = 0;
#endif
    for (int depth = 0; depth <= max_depth; ++depth) {
        Hit hit = trace_closest(ray, 3.0e38);
        if (hit.prim < 0) {
            float w = 1.0;
#ifdef HAS_ENV_MAP_SAMPLING
            if (last_brdf_pdf > 0.0) w = power_heuristic(last_brdf_pdf, env_pdf(ray.dir));
#endif
            sum += throughput * environment(ray.dir) * w;
            break;
        }
        SurfaceHit s = surface_at(ray, hit);
#ifdef HAS_BLEND
        // Camera rays pass a blended layer with probability 1 - alpha: in expectation
        // alpha * (the layer) + (1 - alpha) * (what is behind it), the OVER operator.
        if (depth == 0 && layers < 32 && rng_next(rng) >= blend_alpha(s)) {
            ray = make_ray(offset_ray(s.p, -s.ng, rt.fparams2.x), ray.dir);
            ++layers;
            --depth;
            continue;
        }
#endif
        vec3 Le = emitted(s);
        if (max(Le.r, max(Le.g, Le.b)) > 0.0) {
            float w = 1.0;
#ifdef HAS_EMITTERS
            if (last_brdf_pdf > 0.0) w = power_heuristic(last_brdf_pdf, emitter_pdf(ray, hit, s));
#endif
            sum += throughput * Le * w;
        }
        if (depth == max_depth) break;
        vec3 v = -normalize(ray.dir);
#ifdef HAS_TRANSMISSION
        float transmission = material_transmission(s.material);
        if (transmission > 0.0 && rng_next(rng) < transmission) {
            // Smooth dielectric: reflect or refract by the exact Fresnel term.
            BrdfInput m = brdf_input(s);
            bool thin = material_thin(s.material);
            float eta = thin ? 1.0 : (s.front ? 1.0 / m.ior : m.ior);
            float cos_i = dot(v, s.ng);
            // A thin wall reflects like the interface it stands for but does not bend the ray.
            float F = fresnel_dielectric(cos_i, thin ? 1.0 / m.ior : eta);
            if (rng_next(rng) < F) {
                ray = make_ray(offset_ray(s.p, s.ng, rt.fparams2.x), reflect(-v, s.ng));
            } else {
                ray = make_ray(offset_ray(s.p, -s.ng, rt.fparams2.x), thin ? -v : refract(-v, s.ng, eta));
                throughput *= m.base_color;
            }
            last_brdf_pdf = 0.0;
            continue;
        }
#endif
        BrdfInput m = brdf_input(s);
        sum += throughput * direct_punctual(s, m, v);
#ifdef HAS_EMITTERS
        sum += throughput * direct_emitters(s, m, v, rng, true);
#endif
#ifdef HAS_ENV_MAP_SAMPLING
        {
            float pdf_env;
            vec3 le = sample_env(rng, pdf_env);
            vec3 fc = pdf_env > 0.0 ? brdf_cos_folded(m, s, le, v) : vec3(0.0);
            if (max(fc.r, max(fc.g, fc.b)) > 0.0 &&
                !trace_any(make_ray(offset_ray(s.p, s.ng, rt.fparams2.x), le), 3.0e38)) {
                float w = power_heuristic(pdf_env, brdf_pdf_folded(m, s, v, le));
                sum += throughput * fc * environment(le) * w / pdf_env;
            }
        }
#endif
        vec3 l;
        if (!sample_brdf_folded(m, s, v, rng, l)) break;
        float pdf = brdf_pdf_folded(m, s, v, l);
        if (pdf <= 0.0) break;
        throughput *= brdf_cos_folded(m, s, l, v) / pdf;
        last_brdf_pdf = pdf;
        if (depth >= 3) {
            float survive = clamp(max(throughput.r, max(throughput.g, throughput.b)), 0.05, 0.95);
            if (rng_next(rng) >= survive) break;
            throughput /= survive;
        }
        ray = make_ray(offset_ray(s.p, s.ng, rt.fparams2.x), l);
    }
    return sum;
}
