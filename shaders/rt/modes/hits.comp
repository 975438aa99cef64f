#version 450 core
// Tracer mode `hits`: what each pixel's camera rays see, as shares of its samples: r a passive
// surface, g an emitting one (emission towards the camera, its emissive texture included), b
// nothing (the environment). Emitters are told by what the ray hits, never by brightness; the
// planner's view measurements (engine/rt/view_light.hpp) weight their pixels with it.
#include "../trace_common.glsl"
#include "../materials.glsl"

vec3 radiance(Ray ray, inout Rng rng) {
    Hit hit = trace_closest(ray, 3.0e38);
    if (hit.prim < 0) return vec3(0.0, 0.0, 1.0);
    vec3 e = emitted(surface_at(ray, hit));
    return max(e.r, max(e.g, e.b)) > 0.0 ? vec3(0.0, 1.0, 0.0) : vec3(1.0, 0.0, 0.0);
}
