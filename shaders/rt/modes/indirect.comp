#version 450 core
// Tracer mode `indirect`: one diffuse bounce only (the reference for RSM).
#include "../trace_common.glsl"
#include "../materials.glsl"
#include "../brdf_sampling.glsl"
#include "../direct_light.glsl"

// Shadow rays from the bounce point: every surface blocks the light.
vec3 shadow_visibility(Ray ray, float tmax) { return opaque_visibility(ray, tmax); }

// One diffuse bounce: light that reached the first visible point x after exactly one reflection
// off another surface y (Lambertian at both ends, as RSM models it). The ground truth for RSM.
vec3 radiance(Ray ray, inout Rng rng) {
    Hit hit = trace_seen(ray, 3.0e38);
    if (hit.prim < 0) return vec3(0.0);
    SurfaceHit x = surface_at(ray, hit);
    BrdfInput mx = brdf_input(x);
    vec3 albedo_x = mx.base_color * (1.0 - mx.metallic);
    if (rt.indirect_occlusion != 0) {
        // With occlusion: y is what a cosine-distributed ray from x sees.
        vec3 dir = to_world(sample_cosine_hemisphere(vec2(rng_next(rng), rng_next(rng))), x.ns);
        if (dot(dir, x.ng) <= 0.0) return vec3(0.0);
        Ray bounce = make_ray(offset_ray(x.p, x.ng, rt.ray_offset), dir);
        Hit hy = trace_seen(bounce, 3.0e38);
        if (hy.prim < 0) return vec3(0.0);
        // Cosine sampling: f_x * cos / pdf = albedo_x.
        return albedo_x * lambert_direct_light(surface_at(bounce, hy), -dir, rng);
    }
    // Without occlusion between x and y: y uniform by area over every triangle,
    // L = f_x * L_o(y) * cos_x * cos_y / d^2 / pdf_area(y).
    if (rt.surface_count == 0) return vec3(0.0);
    float u = rng_next(rng);
    int lo = 0, hi = rt.surface_count - 1;
    while (lo < hi) {
        int mid = (lo + hi) / 2;
        if (surfaces[mid].cdf < u) lo = mid + 1; else hi = mid;
    }
    Emitter pick = surfaces[lo];
    RtTriangle tri = load_triangle(int(pick.triangle));
    float su = sqrt(rng_next(rng));
    float u2 = rng_next(rng);
    vec2 bary = vec2(su * (1.0 - u2), su * u2);
    vec3 q = (1.0 - su) * tri.p0.xyz + bary.x * tri.p1.xyz + bary.y * tri.p2.xyz;
    vec3 d = q - x.p;
    float dist2 = dot(d, d);
    if (dist2 <= 0.0) return vec3(0.0);
    vec3 dir = d * inversesqrt(dist2);
    float cos_x = dot(x.ns, dir);
    if (cos_x <= 0.0) return vec3(0.0);
    // The surface record at y as seen from x (front side towards x).
    Ray to_y = make_ray(x.p, d);
    Hit hy;
    hy.t = 1.0;
    hy.prim = int(pick.triangle);
    hy.bary = bary;
    SurfaceHit y = surface_at(to_y, hy);
    if (!y.front && !material_double_sided(y.material)) return vec3(0.0);
    float cos_y = dot(y.ng, -dir);
    if (cos_y <= 0.0) return vec3(0.0);
    float pdf_area = pick.pdf / pick.area;
    return albedo_x * INV_PI * lambert_direct_light(y, -dir, rng) * cos_x * cos_y / (dist2 * pdf_area);
}
