#version 450 core
// Tracer mode `bounce`.
#include "../trace_common.glsl"

// Camera rays plus one cosine-distributed closest-hit ray from each hit: the incoherent
// diffuse-bounce rays of path tracing, for the ray-rate benchmark. Returns the bounce hit's
// normal (0.5 + 0.5 n), black on a miss.
vec3 radiance(Ray ray, inout Rng rng) {
    Hit hit = trace_seen(ray, 3.0e38);
    if (hit.prim < 0) return vec3(0.0);
    SurfaceHit s = surface_at(ray, hit);
    Ray bounce = make_ray(offset_ray(s.p, s.ng, rt.ray_offset), to_world(sample_cosine_hemisphere(vec2(rng_next(rng), rng_next(rng))), s.ng));
    Hit h2 = trace_seen(bounce, 3.0e38);
    if (h2.prim < 0) return vec3(0.0);
    return 0.5 + 0.5 * surface_at(bounce, h2).ns;
}
