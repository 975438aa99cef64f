#version 450 core
// Tracer mode `visibility`.
#include "../trace_common.glsl"
#include "../materials.glsl"

// The ground truth of the raster visibility buffer (debug.view=visibility): the fraction of light
// rt.visibility_light reaching the first visible point, 0 where the surface faces away from it or the
// light sends nothing its way (outside a spot cone, behind a one-sided emitter). Below
// the punctual count: that punctual light; otherwise all emissive triangles (a point drawn by
// power per sample, so the mean is the power-weighted visible fraction).
vec3 radiance(Ray ray, inout Rng rng) {
    Hit hit = trace_seen(ray, 3.0e38);
    if (hit.prim < 0) return vec3(0.0);
    SurfaceHit s = surface_at(ray, hit);
    int li = int(rt.visibility_light);
    if (li < rt.punctual_light_count) {
        vec3 l, E;
        float dist;
        light_incidence(lights[li], s.p, l, E, dist);
        if (dot(s.ns, l) <= 0.0 || dot(s.ng, l) <= 0.0 || max(E.r, max(E.g, E.b)) <= 0.0) return vec3(0.0);
        return vec3(trace_any(make_ray(offset_ray(s.p, s.ng, rt.ray_offset), l), dist) ? 0.0 : 1.0);
    }
#ifdef HAS_EMITTERS
    float u = rng_next(rng);
    int lo = 0, hi = rt.emitter_count - 1;
    while (lo < hi) {
        int mid = (lo + hi) / 2;
        if (emitters[mid].cdf < u) lo = mid + 1; else hi = mid;
    }
    RtTriangle tri = load_triangle(int(emitters[lo].triangle));
    float su = sqrt(rng_next(rng));
    float u2 = rng_next(rng);
    vec3 q = (1.0 - su) * tri.p0.xyz + su * (1.0 - u2) * tri.p1.xyz + su * u2 * tri.p2.xyz;
    vec3 nl = normalize(cross(tri.p1.xyz - tri.p0.xyz, tri.p2.xyz - tri.p0.xyz));
    vec3 d = q - s.p;
    float cos_l = dot(nl, -d);
    if (material_double_sided(floatBitsToInt(tri.p0.w))) cos_l = abs(cos_l);
    if (dot(s.ns, d) <= 0.0 || dot(s.ng, d) <= 0.0 || cos_l <= 0.0) return vec3(0.0);
    vec3 origin = offset_ray(s.p, s.ng, rt.ray_offset);
    vec3 target = offset_ray(q, dot(nl, -d) > 0.0 ? nl : -nl, rt.ray_offset);
    return vec3(trace_any(make_ray(origin, target - origin), 1.0) ? 0.0 : 1.0);
#else
    return vec3(0.0);
#endif
}
