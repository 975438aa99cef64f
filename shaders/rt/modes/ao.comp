#version 450 core
// Tracer mode `ao`: ambient occlusion of the first visible point within the radius rt.ao_radius
// (ao.radius, the radius SSAO uses): the cosine-weighted unoccluded fraction, 1 on a miss.
#include "../trace_common.glsl"

vec3 radiance(Ray ray, inout Rng rng) {
    Hit hit = trace_seen(ray, 3.0e38);
    if (hit.prim < 0) return vec3(1.0);
    SurfaceHit s = surface_at(ray, hit);
    vec3 dir = to_world(sample_cosine_hemisphere(vec2(rng_next(rng), rng_next(rng))), s.ng);
    bool occluded = trace_any(make_ray(offset_ray(s.p, s.ng, rt.ray_offset), dir * rt.ao_radius), 1.0);
    return vec3(occluded ? 0.0 : 1.0);
}
