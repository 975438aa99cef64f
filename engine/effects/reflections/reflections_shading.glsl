// What the lighting reads from the reflections effect (included by shaders/lighting/shading.glsl):
// the probes captured by the env_probe pass and prefiltered like the static environment.
#include "effects/reflections/reflections_data.h"

layout(binding = REFLECTIONS_PROBES_UNIT) uniform samplerCubeArray t_probes;   // bound when reflections.probes > 0
layout(std430, binding = REFLECTIONS_PROBES_BINDING) readonly buffer Probes { ProbeData probes[]; };

// The probe that lights p on a surface with these properties: of those whose box (or radius)
// contains p and that light such a surface, the nearest; -1 if none.
int probe_at(vec3 p, BrdfInput bi, float transmission) {
    int best = -1;
    float best_d = 3.0e38;
    for (int k = 0; k < reflections.probes; ++k) {
        ProbeData pr = probes[k];
        if (pr.reflective_only >= 0.0 && transmission <= 0.0 && !(bi.metallic > 0.5 && bi.roughness < pr.reflective_only)) continue;
        float d = distance(p, pr.position);
        bool inside = pr.has_box > 0.5
            ? all(greaterThanEqual(p, pr.box_min - 1e-4)) && all(lessThanEqual(p, pr.box_max + 1e-4))
            : d <= pr.radius;
        if (inside && d < best_d) {
            best = k;
            best_d = d;
        }
    }
    return best;
}

// Lagarde & Zanuttini 2012, "Local image-based lighting with parallax-corrected cubemaps": the
// ray p + t r leaves the probe's box at the point the probe saw in direction (hit - position).
vec3 probe_direction(ProbeData pr, vec3 p, vec3 r) {
    if (pr.has_box < 0.5) return r;
    vec3 rs = mix(r, mix(vec3(1e-8), vec3(-1e-8), lessThan(r, vec3(0.0))), lessThan(abs(r), vec3(1e-8)));
    vec3 far_t = max((pr.box_max - p) / rs, (pr.box_min - p) / rs);
    float t = max(min(min(far_t.x, far_t.y), far_t.z), 0.0);
    vec3 d = p + r * t - pr.position;
    return dot(d, d) > 1e-12 ? d : r;
}

// Radiance from probe k arriving at p from direction r, prefiltered for `roughness`. A reflection
// (`reflected`) leaves out the emitters that the area lights shade analytically: the capture
// stored their luminance in alpha, filtered as the colour was, and the colour is scaled to
// take it away. Light seen through a transmissive surface keeps them (the area lights only
// reflect).
vec3 probe_radiance(int k, vec3 p, vec3 r, float roughness, bool reflected) {
    vec4 c = textureLod(t_probes, vec4(probe_direction(probes[k], p, r), float(k)),
                        roughness * float(max(reflections.levels - 1, 0)));
    if (!reflected || c.a <= 0.0) return c.rgb;
    float lum = dot(c.rgb, LUMINANCE_WEIGHTS);
    return lum > c.a ? c.rgb * (1.0 - c.a / lum) : vec3(0.0);
}
