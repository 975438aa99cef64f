// What the reflections effect adds to the lighting (included by shaders/lighting/shading.glsl
// through the registry): the probes captured by the env_probe pass and prefiltered like the
// static environment as reflection sources (hooks reflection_source and reflection_radiance),
// refraction through transmissive surfaces (hook refraction) and the capture views (hook
// capture_view).
#include "effects/reflections/reflections_data.h"

layout(binding = REFLECTIONS_PROBES_UNIT) uniform samplerCubeArray t_probes;   // bound when reflections.probes > 0
layout(std430, binding = REFLECTIONS_PROBES_BINDING) readonly buffer Probes { ProbeData probes[]; };
// The distance from each probe to the surface it saw in each direction (probe_distance.comp).
layout(binding = REFLECTIONS_DISTANCE_UNIT) uniform samplerCubeArray t_probe_distance;

// The probe that lights p on a surface with these properties: of those whose box (or radius)
// contains p and that light such a surface, the nearest; -1 if none.
int reflections_reflection_source(vec3 p, BrdfInput bi, float transmission) {
#ifdef REFLECTIONS_NO_PROBES
    return -1;  // reflections.probes 0 (reflections.cpp)
#else
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
#endif
}

// Where the ray p + t r meets the surroundings probe k saw, as a direction from the probe.
// A probe with a box: Lagarde & Zanuttini 2012, "Local image-based lighting with
// parallax-corrected cubemaps": the ray leaves the box at the point the probe saw in direction
// (hit - position). Without one: the probe's distance cube is a distance impostor (Szirmay-Kalos
// et al. 2005, "Approximate Ray-Tracing on the GPU with Distance Impostors"): with o = p - probe,
// f(t) = |o + t r| - distance(o + t r) is negative while the ray point is nearer than what the
// probe saw in its direction; a search over t (t = L s / (1 - s), s in steps of 1/12, L the
// distance the probe saw along r) finds where f turns positive and secant steps refine it. No
// crossing: the ray leaves the probe's surroundings and the lookup is along r.
vec3 probe_direction(int k, vec3 p, vec3 r) {
    ProbeData pr = probes[k];
    if (pr.has_box > 0.5) {
        vec3 rs = mix(r, mix(vec3(1e-8), vec3(-1e-8), lessThan(r, vec3(0.0))), lessThan(abs(r), vec3(1e-8)));
        vec3 far_t = max((pr.box_max - p) / rs, (pr.box_min - p) / rs);
        float t = max(min(min(far_t.x, far_t.y), far_t.z), 0.0);
        vec3 d = p + r * t - pr.position;
        return dot(d, d) > 1e-12 ? d : r;
    }
    if (reflections.parallax == 0) return r;
    vec3 o = p - pr.position;
    float L = textureLod(t_probe_distance, vec4(r, float(k)), 0.0).r;
    if (L >= 0.5 * REFLECTIONS_FAR) L = max(length(o), 1e-3);
    // At t = 0, p itself: in front of what the probe saw (the objects it serves are not
    // captured) or on it (a shared probe captures the objects it serves but not their own).
    float t0 = 0.0;
    float f0 = dot(o, o) > 1e-12 ? length(o) - textureLod(t_probe_distance, vec4(o, float(k)), 0.0).r : -L;
    f0 = min(f0, -1e-4 * L);
    const int steps = 12;
    for (int i = 1; i < steps; ++i) {
        float s = float(i) / float(steps);
        float t1 = L * s / (1.0 - s);
        vec3 q = o + t1 * r;
        float f1 = length(q) - textureLod(t_probe_distance, vec4(q, float(k)), 0.0).r;
        if (f1 > 0.0) {
            // Secant steps between the last point in front (t0, f0 < 0) and this one behind.
            for (int j = 0; j < 3; ++j) {
                float t = t0 - f0 * (t1 - t0) / (f1 - f0);
                vec3 qm = o + t * r;
                float fm = length(qm) - textureLod(t_probe_distance, vec4(qm, float(k)), 0.0).r;
                if (fm > 0.0) {
                    t1 = t;
                    f1 = fm;
                } else {
                    t0 = t;
                    f0 = fm;
                }
            }
            vec3 d = o + (t0 - f0 * (t1 - t0) / (f1 - f0)) * r;
            return dot(d, d) > 1e-12 ? d : r;
        }
        t0 = t1;
        f0 = f1;
    }
    return r;
}

// Radiance from probe k arriving at p from direction r, prefiltered for `roughness`. A reflection
// (`reflected`) leaves out the emitters that the area lights shade analytically: the capture
// stored their luminance in alpha, filtered as the colour was, and the colour is scaled to
// take it away. Light seen through a transmissive surface keeps them (the area lights only
// reflect).
vec3 reflections_reflection_radiance(int k, vec3 p, vec3 r, float roughness, bool reflected) {
    vec4 c = textureLod(t_probes, vec4(probe_direction(k, p, r), float(k)),
                        roughness * float(max(reflections.levels - 1, 0)));
    if (!reflected || c.a <= 0.0) return c.rgb;
    float lum = dot(c.rgb, LUMINANCE_WEIGHTS);
    return lum > c.a ? c.rgb * (1.0 - c.a / lum) : vec3(0.0);
}

// Transmissive surfaces show what lies behind them, refracted (without: opaque dielectrics).
bool reflections_refraction() {
#ifdef REFLECTIONS_NO_REFRACTION
    return false;  // reflections.refraction 0 (reflections.cpp)
#else
    return reflections.refraction != 0;
#endif
}

// The env_probe pass draws this view into a probe: alpha carries the luminance of the emission
// the area lights add analytically, which reflections_reflection_radiance leaves out.
bool reflections_capture_view() { return reflections.capture != 0; }
