// KHR_lights_punctual evaluation, radiometric (point/spot intensity in W/sr, directional in W/m^2).
#include "math.glsl"
#include "gpu/scene_blocks.h"

const int LIGHT_DIRECTIONAL = 0;
const int LIGHT_POINT = 1;
const int LIGHT_SPOT = 2;
// A small planar piece of an emissive surface, as a Lambertian emitter: the rasterizer's
// approximation of area lights (the ray tracer samples the emissive triangles themselves).
const int LIGHT_AREA_PATCH = 3;

// Range window recommended by KHR_lights_punctual: smooth cut-off at `range`.
float range_attenuation(float distance, float range) {
    if (range <= 0.0) return 1.0;
    float r = distance / range;
    float w = saturate(1.0 - r * r * r * r);
    return w * w;
}

// How far a point or spot light reaches in the raster: its range, else its cutoff distance
// (lights.cutoff, render/gpu_scene.hpp); 0: unbounded.
float light_reach(LightData light) { return light.range > 0.0 ? light.range : light.cutoff; }

// Direction towards the light (l) and irradiance at normal incidence (E) for a surface point.
void light_incidence(LightData light, vec3 p, out vec3 l, out vec3 E, out float distance) {
    int type = int(light.type);
    if (type == LIGHT_DIRECTIONAL) {
        l = -light.direction;
        E = light.color.rgb;
        distance = 1e30;
        return;
    }
    vec3 d = light.position - p;
    float dist2 = max(dot(d, d), 1e-12);
    distance = sqrt(dist2);
    l = d / distance;
    if (type == LIGHT_AREA_PATCH) {
        float cos_e = dot(light.direction, -l);
        if (light.patch_two_sided > 0.5) cos_e = abs(cos_e);
        // Below a patch's own size the point-emitter model breaks down: bound the 1/d^2.
        E = light.color.rgb * max(cos_e, 0.0) / max(dist2, light.patch_area);
        return;
    }
    float att = range_attenuation(distance, light.range) / dist2;
#ifndef LIGHTS_UNBOUNDED
    // A light without a range in the raster: 1/d^2 less its value at the cutoff distance, so that
    // it reaches 0 there, and no point gets more than that constant less (the tracer, which
    // defines LIGHTS_UNBOUNDED, keeps the whole 1/d^2).
    if (light.range <= 0.0 && light.cutoff > 0.0) att = max(att - 1.0 / (light.cutoff * light.cutoff), 0.0);
#endif
    if (type == LIGHT_SPOT) {
        float cd = dot(light.direction, -l);
        float s = saturate(cd * light.spot_scale + light.spot_offset);
        att *= s * s;
    }
    E = light.color.rgb * att;
}
