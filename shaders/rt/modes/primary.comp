#version 450 core
// Tracer mode `primary`.
#include "../trace_common.glsl"

// Camera rays only: the shading normal (0.5 + 0.5 n), black on a miss. For ray-rate benchmarks
// and as a debug view of what the tracer sees.
vec3 radiance(Ray ray, inout Rng rng) {
    Hit hit = trace_seen(ray, 3.0e38);
    if (hit.prim < 0) return vec3(0.0);
    return 0.5 + 0.5 * surface_at(ray, hit).ns;
}
