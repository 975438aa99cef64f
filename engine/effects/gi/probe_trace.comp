#version 450 core
// GI probes, step 1 of an update (engine/effects/gi/gi.cpp): every probe of the batch traces
// gi.rays_per_probe rays with the tracer's BVH, in spherical Fibonacci directions under this
// iteration's random rotation. A ray records the light leaving what it hits towards the probe
// and its distance: the direct light the hit reflects back along the ray with its full BRDF (the
// tracer's next-event estimation, as in path mode: shadow rays, its own light sampling), so that
// light a metal or glossy surface sends towards the probe is counted, plus the previous
// iteration's probes for the bounces before (both lobes, split sum). A transmissive surface is what the
// tracer's camera paths make of it (path.comp, the same dielectric_scatter): with probability
// `transmission` a dielectric, smooth or rough, that reflects or refracts the ray, with no direct
// light of its own (next-event estimation cannot connect a punctual light through it), and the
// ray goes on to what lies beyond, absorbed inside solid glass as in path mode; otherwise the
// opaque BRDF. Emission is left out: the raster shades emitters as direct light. One ray per
// invocation; work group y: the probe.
#define RT_NO_CAMERA
#include "rt/trace_common.glsl"
#include "rt/materials.glsl"
#include "rt/brdf_sampling.glsl"
#include "rt/direct_light.glsl"
#include "rt/dielectric.glsl"
#include "effects/gi/gi_sample.glsl"

layout(std430, binding = GI_RAYS_BINDING) writeonly buffer GiRays { vec4 gi_rays[]; };  // per ray two entries: rgb radiance, a distance (< 0: a back face); the direction

vec3 shadow_visibility(Ray ray, float tmax) { return opaque_visibility(ray, tmax); }

// Ray i of n: a spherical Fibonacci point set (Keinert et al. 2015), nearly uniform on the sphere.
vec3 gi_ray_direction(int i, int n) {
    const float golden_angle = 2.39996322972865332;  // pi (3 - sqrt 5)
    float z = 1.0 - (2.0 * float(i) + 1.0) / float(n);
    float r = sqrt(max(1.0 - z * z, 0.0));
    float phi = float(i) * golden_angle;
    return normalize(mat3(gi.rotation) * vec3(cos(phi) * r, sin(phi) * r, z));
}

// The split sum's scale and bias (A, B) of the specular lobe's directional albedo F0 A + B, by
// the analytic fit of Karis 2014 ("Physically Based Shading on Mobile", after Lazarov 2013): the
// probes have no BRDF table bound, and a later bounce needs only its energy.
vec2 gi_env_brdf(float roughness, float NdotV) {
    vec4 r = roughness * vec4(-1.0, -0.0275, -0.572, 0.022) + vec4(1.0, 0.0425, 1.04, -0.04);
    float a004 = min(r.x * r.x, exp2(-9.28 * NdotV)) * r.x + r.y;
    return vec2(-1.04, 1.04) * a004 + r.zw;
}

// Dielectric vertices a probe ray passes before it counts as lost (a solid glass object
// takes two; total internal reflection a few more).
const int GI_MAX_DIELECTRIC_VERTICES = 8;

// How fast the surface's normal turns at a hit, in radians per unit of length: 1 / radius on a
// sphere; on a triangle the largest turn of its vertex normals per edge length (0 on a flat face,
// 1 / radius on a smooth mesh of a sphere).
float surface_curvature(Hit hit) {
#ifndef RT_NO_SPHERES
    if (hit.prim >= rt.triangle_count) return 1.0 / max(spheres[hit.prim - rt.triangle_count].radius, 1e-30);
#endif
    RtTriangle tri = load_triangle(hit.prim);
    float k01 = length(tri.n1.xyz - tri.n0.xyz) / max(length(tri.p1.xyz - tri.p0.xyz), 1e-30);
    float k12 = length(tri.n2.xyz - tri.n1.xyz) / max(length(tri.p2.xyz - tri.p1.xyz), 1e-30);
    float k20 = length(tri.n0.xyz - tri.n2.xyz) / max(length(tri.p0.xyz - tri.p2.xyz), 1e-30);
    return max(k01, max(k12, k20));
}

// The light leaving the surface a probe ray hit (y, front side or double-sided) back along the
// ray, as the tracer's camera paths see it: transmissive surfaces pass the ray on (reflected or
// refracted), the first other surface gives its direct light and the previous probes' bounce.
vec3 probe_ray_radiance(Ray ray, Hit hit, SurfaceHit y, inout Rng rng) {
    vec3 throughput = vec3(1.0);
    // A probe ray stands for a cone of the sphere's 4 pi / n: half-angle 2 / sqrt(n). Where it
    // meets a curved surface, the normal turns by (footprint radius x curvature) across the
    // cone, and the light the cone's surface sends back is the BRDF's lobe widened by that turn
    // (as a distribution of normals widens it: Kaplanyan et al. 2016, "Filtering Distributions
    // of Normals for Shading Antialiasing"; ray cones: Akenine-Moeller et al. 2019). One ray
    // through one point of a sphere's highlight otherwise carries the highlight of the whole
    // cone: random:20035's metal sphere, 0.4 m across, 0.5 m from a probe, gave one ray of 64
    // 600 times the room's radiance, and its probe's irradiance of that update 20 times its mean.
    const float cone = 2.0 / sqrt(float(gi.rays_per_probe));
    float travelled = hit.t * length(ray.dir);
    for (int k = 0;; ++k) {
        vec3 v = -normalize(ray.dir);
        float transmission = material_transmission(y);
        if (transmission > 0.0 && rng_next(rng) < transmission) {
            if (k == GI_MAX_DIELECTRIC_VERTICES) return vec3(0.0);
            vec3 l, w;
            bool below;
            if (!dielectric_scatter(y, brdf_input(y), v, rng, l, w, below)) return vec3(0.0);
            ray = make_ray(offset_ray(y.p, below ? -y.ng : y.ng, rt.ray_offset), l);
            throughput *= w;
            hit = trace_closest(ray, 3.0e38);
            if (hit.prim < 0) return throughput * environment(ray.dir);  // as a probe ray that misses: the sky
            y = surface_at(ray, hit);
            travelled += hit.t * length(ray.dir);
            throughput *= volume_transmittance(y, hit.t * length(ray.dir));
            // Inside glass every hit is a back face of the glass; a one-sided opaque back face
            // beyond it sends nothing.
            if (!y.front && !material_double_sided(y.material) && material_transmission(y) <= 0.0) return vec3(0.0);
            continue;
        }
        // Direct light reflected towards the ray's origin by the hit's whole BRDF: the diffuse
        // lobe and the specular one, which a metal has alone. Emitters are sampled without MIS:
        // the probe ray does not go on to sample the BRDF.
        BrdfInput m = brdf_input(y);
        // Path regularization (Kaplanyan & Dachsbacher 2013, "Path Space Regularization for
        // Holistic and Robust Light Transport"): a probe ray sees a surface at roughness 0.25 at
        // least. A probe needs what a surface sends towards its neighbourhood, and a narrow
        // lobe's highlight of a point light, met by one or two of 64 rays, made the probes
        // noisy: random:44 (a metal sphere of roughness 0.24) moved by +-5 % with gi.rays and
        // failed at +9.5 %; +7.9 % at a floor of 0.25, +4.0 % at 0.3, +2.0 % at 0.35. A wider
        // floor reshapes the light a smooth metal throws onto the room (random:7, a metal wall
        // under three spots: blocks 0.034 at 0.25, 0.038 at 0.3 over its bound 0.0376).
        m.roughness = max(m.roughness, 0.25);
        float turn = travelled * cone * surface_curvature(hit);
        float alpha = m.roughness * m.roughness, NdotV0 = saturate(dot(y.ns, v));
        vec2 albedo_before = gi_env_brdf(m.roughness, NdotV0);
        m.roughness = sqrt(min(sqrt(alpha * alpha + turn * turn), 1.0));
        // The widened single-scattering lobe reflects less in all than the narrow one, whose
        // light it spreads (at alpha 1 about half of it): the specular lobe keeps its energy,
        // by the split sum's directional albedo (F0 = 1) before and after. The metal's whole
        // light is that lobe's; a dielectric's specular share, a few per cent, is left as it is.
        vec2 albedo_after = gi_env_brdf(m.roughness, NdotV0);
        float keep = mix(1.0, (albedo_before.x + albedo_before.y) / max(albedo_after.x + albedo_after.y, 1e-4), m.metallic);
        vec3 L = direct_punctual(y, m, v);
#ifdef HAS_EMITTERS
        if (rt.emitter_count > 0) L += direct_emitters(y, m, v, rng, false);
#endif
        // The bounces before: the previous iteration's probes, reflected as the raster's
        // ambient term reflects its surroundings (split sum): the irradiance E(n) for the
        // diffuse lobe, and for the specular lobe the radiance around the mirror direction r,
        // approximated by E(r) / pi (the cosine-weighted mean radiance about r). A metal thus
        // passes on light from the lit room, not only from the lights.
        if (gi.on > 0.5) {
            float NdotV = saturate(dot(y.ns, v));
            vec3 E = gi_irradiance(y.p, y.ns, v);
            vec3 Er = E;
            if (m.metallic > 0.0) {
                vec3 r = reflect(-v, y.ns);
                // The lobe's dominant direction (Lagarde & de Rousiers 2014, "Moving Frostbite
                // to PBR"): towards the normal the rougher the surface.
                float a = m.roughness * m.roughness, smooth_ = 1.0 - a;
                Er = gi_irradiance(y.p, normalize(mix(y.ns, r, smooth_ * (sqrt(smooth_) + a))), v);
            }
            L += brdf_ambient(m, NdotV, gi_env_brdf(m.roughness, NdotV), E, Er * INV_PI, 0.0, vec3(0.0));
        }
        return throughput * L * keep;
    }
    return vec3(0.0);
}

// What a probe ray sees at `hit`. A back face (the probe is inside geometry or behind a one-sided
// wall) counts as such only if no front face lies at the same distance: where two faces coincide
// (a box standing on a floor: its bottom and the floor's top) the tracer returns either of them by
// float rounding alone, and the probe's irradiance and relocation then changed with the scene's
// placement (a box moved by its own size flipped a probe's move). Such a pair is the front face.
SurfaceHit probe_ray_face(Ray ray, Hit hit, out bool back) {
    SurfaceHit y = surface_at(ray, hit);
    back = !y.front && !material_double_sided(y.material);
    if (!back) return y;
    float d = 1e-4 * min(gi.spacing.x, min(gi.spacing.y, gi.spacing.z));
    Ray around = make_ray(y.p - ray.dir * d, ray.dir);
    Hit h = trace(around, 2.0 * d, false, true);  // front faces (and two-sided ones) only
    if (h.prim < 0) return y;
    SurfaceHit f = surface_at(around, h);
    if (!f.front && !material_double_sided(f.material)) return y;
    back = false;
    return f;
}

void main() {
    int rays = gi.rays_per_probe;
    int probe = gi.first_probe + int(gl_WorkGroupID.y);
    int total = gi.probe_counts.x * gi.probe_counts.y * gi.probe_counts.z;
    int ray_index = int(gl_WorkGroupID.x) * 64 + int(gl_LocalInvocationIndex);
    if (probe >= total || ray_index >= rays) return;
    vec3 dir = gi_ray_direction(ray_index, rays);
    Ray ray = make_ray(gi_probe_position(gi_probe_coord(probe)), dir);
    Rng rng = rng_init(floatBitsToUint(gi.seed), uint(probe * rays + ray_index), uint(gi.iteration));
    Hit hit = trace_closest(ray, 3.0e38);
    // A ray that misses brings the sky (the raster takes the sky's diffuse light from the probes),
    // in every update: gi.on says only whether the previous update's probes are read (a bounce
    // more), which they are not in the first update or when a single bounce is planned.
    vec4 result = vec4(gi.on > -0.5 ? environment(dir) : vec3(0.0), gi.miss_distance);
    vec4 face = vec4(0.0);  // relocation's trace: the plane of the face met (none: a miss)
    if (hit.prim >= 0 && gi.on < -0.5) {
        // Relocation's trace (gi.cpp): how far the ray met a surface, negative for a back face,
        // and the face's plane: its normal towards the probe and the probe's distance to it.
        // probe_relocate.comp moves a probe by planes, not by rays: rays that meet one plane
        // at nearly the same distance then agree on the move, whichever of them is nearest.
        bool back;
        SurfaceHit y = probe_ray_face(ray, hit, back);
        result.a = back ? -0.2 * hit.t : min(hit.t, gi.miss_distance);
        face = vec4(y.ng, hit.t * abs(dot(dir, y.ng)));
    } else if (hit.prim >= 0) {
        bool back;
        SurfaceHit y = probe_ray_face(ray, hit, back);
        if (back) {
            // Inside geometry (or behind a one-sided wall): no light, and a short negative distance
            // so that the update counts it and the Chebyshev test keeps the probe from leaking.
            result = vec4(0.0, 0.0, 0.0, -0.2 * hit.t);
        } else {
            result = vec4(probe_ray_radiance(ray, hit, y, rng), min(hit.t, gi.miss_distance));
        }
    }
    if (any(isnan(result)) || any(isinf(result.rgb))) {
        atomicAdd(nonfinite_samples, 1u);
        result = vec4(0.0, 0.0, 0.0, gi.miss_distance);
    }
    gi_rays[2 * (probe * rays + ray_index)] = result;
    gi_rays[2 * (probe * rays + ray_index) + 1] = gi.on < -0.5 ? face : vec4(dir, 0.0);
}
