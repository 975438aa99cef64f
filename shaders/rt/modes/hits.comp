#version 450 core
// Tracer mode `hits`: what each pixel's camera rays see, as shares of its samples: r a passive
// surface, g an emitting one (emission towards the camera, its emissive texture included), b the
// diffuse part of the passive surfaces seen (1 - metallic)(1 - transmission): the share of their
// light that diffuse interreflection, not a mirror image, makes. Nothing hit (the environment) is
// 1 - r - g. Emitters are told by what the ray hits, never by brightness; the planner's view
// measurements (engine/rt/view_light.hpp) weight their pixels with it.
#include "../trace_common.glsl"
#include "../materials.glsl"

vec3 radiance(Ray ray, inout Rng rng) {
    Hit hit = trace_seen(ray, 3.0e38);
    if (hit.prim < 0) return vec3(0.0);
    SurfaceHit s = surface_at(ray, hit);
    vec3 e = emitted(s);
    if (max(e.r, max(e.g, e.b)) > 0.0) return vec3(0.0, 1.0, 0.0);
    BrdfInput m = brdf_input(s);
    return vec3(1.0, 0.0, (1.0 - m.metallic) * (1.0 - saturate(material_transmission(s))));
}
