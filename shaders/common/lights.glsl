// KHR_lights_punctual evaluation, radiometric (point/spot intensity in W/sr, directional in W/m^2).
#include "math.glsl"

const int LIGHT_DIRECTIONAL = 0;
const int LIGHT_POINT = 1;
const int LIGHT_SPOT = 2;
// A small planar piece of an emissive surface, as a Lambertian emitter: the rasterizer's
// approximation of area lights (the ray tracer samples the emissive triangles themselves).
const int LIGHT_AREA_PATCH = 3;

struct PunctualLight {
    vec4 position_type;    // xyz world position, w type
    vec4 direction_range;  // xyz direction the light points to (patch: its normal), w range (0: infinite)
                           // (patch: 1 if it emits from both sides)
    vec4 color;            // rgb = color * intensity (patch: radiance * area, W/sr at normal incidence)
    vec4 cone;             // spot: x = 1 / (cos inner - cos outer), y = -cos outer * x; patch: x = area
};

// Range window recommended by KHR_lights_punctual: smooth cut-off at `range`.
float range_attenuation(float distance, float range) {
    if (range <= 0.0) return 1.0;
    float r = distance / range;
    float w = saturate(1.0 - r * r * r * r);
    return w * w;
}

// Direction towards the light (l) and irradiance at normal incidence (E) for a surface point.
void light_incidence(PunctualLight light, vec3 p, out vec3 l, out vec3 E, out float distance) {
    int type = int(light.position_type.w);
    if (type == LIGHT_DIRECTIONAL) {
        l = -light.direction_range.xyz;
        E = light.color.rgb;
        distance = 1e30;
        return;
    }
    vec3 d = light.position_type.xyz - p;
    float dist2 = max(dot(d, d), 1e-12);
    distance = sqrt(dist2);
    l = d / distance;
    if (type == LIGHT_AREA_PATCH) {
        float cos_e = dot(light.direction_range.xyz, -l);
        if (light.direction_range.w > 0.5) cos_e = abs(cos_e);
        // Below a patch's own size the point-emitter model breaks down: bound the 1/d^2.
        E = light.color.rgb * max(cos_e, 0.0) / max(dist2, light.cone.x);
        return;
    }
    float att = range_attenuation(distance, light.direction_range.w) / dist2;
    if (type == LIGHT_SPOT) {
        float cd = dot(light.direction_range.xyz, -l);
        float s = saturate(cd * light.cone.x + light.cone.y);
        att *= s * s;
    }
    E = light.color.rgb * att;
}
