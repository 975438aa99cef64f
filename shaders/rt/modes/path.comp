#version 450 core
#define RT_OWN_MAIN  // main() below: samples scheduled per lane
// Tracer modes `path` and `direct` (path with one bounce, rt.max_depth = 1).
#include "../trace_common.glsl"
#include "../materials.glsl"
#include "../brdf_sampling.glsl"
#include "../env_sampling.glsl"
#include "../direct_light.glsl"
#ifdef HAS_TRANSMISSION
#include "../dielectric.glsl"
#endif

// Shadow rays: every surface blocks the light (transmissive ones too; refraction is sampled).
vec3 shadow_visibility(Ray ray, float tmax) { return opaque_visibility(ray, tmax); }

// Unidirectional path tracing with next-event estimation (punctual lights always, emissive
// triangles with MIS against BRDF sampling), Russian roulette after three bounces.
//
// Scheduling (llvmpipe's SIMD lanes stay busy): each invocation traces its pixel's dispatch_samples() samples one after
// the other, one bounce per iteration of one loop, and starts its next sample as soon as a path
// ends. llvmpipe runs 8 invocations in the SIMD lanes of a thread, and a lane whose path the
// roulette ended early used to idle until the longest path of its 8 was done; here it starts its
// next camera ray instead. Every sample is the same as when traced alone (its random stream
// depends on seed, pixel and sample index only), so the image does not change.
struct PathState {
    Ray ray;
    Rng rng;
    vec3 sum;
    vec3 throughput;
    float last_brdf_pdf;  // 0: the last bounce was specular-delta or the camera
    int depth;
    // rt.caustics_only: 0 before the first diffuse or glossy vertex, 1 after it, 2 once a glass
    // or mirror vertex followed it (every later vertex glass or a mirror too: a caustic path).
    int caustic_phase;
#ifdef HAS_BLEND
    int layers;
#endif
};

PathState path_start(ivec2 pixel, uint index, uint sample_index) {
    PathState p;
    p.rng = rng_init(uint(rt.seed), index, sample_index);
    p.ray = camera_ray(pixel, index, sample_index, p.rng);
    p.sum = vec3(0.0);
    p.throughput = vec3(1.0);
    p.last_brdf_pdf = 0.0;
    p.depth = 0;
    p.caustic_phase = 0;
#ifdef HAS_BLEND
    p.layers = 0;
#endif
    return p;
}

// rt.caustics_only (ray_tracer.hpp): a metal smoother than this is a mirror (kCausticMirrorRoughness).
const float kCausticMirrorRoughness = 0.3;
// Whether light reaching the path now is counted: always, or only on a caustic path.
bool counted(PathState p) { return rt.caustics_only == 0.0 || p.caustic_phase == 2; }
// rt.emitters_only: the punctual lights, the environment and unlit colours add nothing; emission does.
bool other_light(PathState p) { return counted(p) && rt.emitters_only == 0.0; }

// One vertex of the path: the closest hit along p.ray, its emission, direct light and the next
// direction. Returns true when the path has ended (p.sum is then the sample's radiance).
bool path_step(inout PathState p) {
    int max_depth = rt.max_depth;
    Hit hit = trace_seen(p.ray, 3.0e38);
    // rt.camera_hides_emission: camera rays do not see emission or the environment; the image is then the
    // light that surfaces reflect (the planner's view measurements).
    bool seen = p.depth > 0 || rt.camera_hides_emission == 0.0;
    if (hit.prim < 0) {
        if (!seen || !other_light(p)) return true;
        float w = 1.0;
#ifdef HAS_ENV_MAP_SAMPLING
        if (p.last_brdf_pdf > 0.0) w = power_heuristic(p.last_brdf_pdf, env_pdf(p.ray.dir));
#endif
        p.sum += p.throughput * environment(p.ray.dir) * w;
        return true;
    }
    SurfaceHit s = surface_at(p.ray, hit);
#ifdef HAS_TRANSMISSION
    // Absorption along the segment just travelled, if it ran inside a solid transmissive volume.
    p.throughput *= volume_transmittance(s, hit.t * length(p.ray.dir));
#endif
#ifdef HAS_BLEND
    // Camera rays pass a blended layer with probability 1 - alpha: in expectation
    // alpha * (the layer) + (1 - alpha) * (what is behind it), the OVER operator.
    if (p.depth == 0 && p.layers < 32 && rng_next(p.rng) >= blend_alpha(s)) {
        p.ray = make_ray(offset_ray(s.p, -s.ng, rt.ray_offset), p.ray.dir);
        ++p.layers;
        return false;
    }
#endif
#ifdef MATERIAL_LAYERS
    if (surface_unlit(s)) {
        if (seen && other_light(p)) p.sum += p.throughput * unlit_color(s);
        return true;
    }
#endif
    vec3 Le = emitted(s);
    if (seen && counted(p) && max(Le.r, max(Le.g, Le.b)) > 0.0) {
        float w = 1.0;
#ifdef HAS_EMITTERS
        if (p.last_brdf_pdf > 0.0) w = power_heuristic(p.last_brdf_pdf, emitter_pdf(p.ray, hit, s));
#endif
        p.sum += p.throughput * Le * w;
    }
    if (p.depth >= max_depth) return true;
    vec3 v = -normalize(p.ray.dir);
#ifdef HAS_TRANSMISSION
    float transmission = material_transmission(s);
    if (transmission > 0.0 && rng_next(p.rng) < transmission) {
        // A dielectric interface, smooth or rough (dielectric_scatter). No next-event estimation
        // of emitters and sky here (light is not connected through the interface), so the next
        // hit's emission counts in full (last_brdf_pdf 0) and the sampled direction alone carries
        // the transmitted light. Punctual lights, which no sampled direction finds, are reflected
        // by the interface's specular lobe (an outside face: a solid's inside sees none) where the
        // camera sees the interface, directly or through other interfaces (last_brdf_pdf 0). After
        // a diffuse or glossy bounce that light would be a caustic: the light a glass block
        // reflects onto the ceiling, which for smooth glass only a path hitting the highlight's
        // 1e-3 lobe finds (noise, not a reference), and which the raster does not model; it is
        // left out like the caustic through the glass.
        BrdfInput mi = brdf_input(s);
        if (p.caustic_phase == 1) p.caustic_phase = 2;
        if (rt.dielectric_highlights != 0.0 && other_light(p) && p.last_brdf_pdf == 0.0 && (s.front || material_thin(s.material)))
            p.sum += p.throughput * direct_punctual_specular(s, mi, v);
        vec3 l, w;
        bool below;
        if (!dielectric_scatter(s, mi, v, p.rng, l, w, below)) return true;
        p.ray = make_ray(offset_ray(s.p, below ? -s.ng : s.ng, rt.ray_offset), l);
        p.throughput *= w;
        p.last_brdf_pdf = 0.0;
        return ++p.depth > max_depth;
    }
#endif
    BrdfInput m = brdf_input(s);
    if (rt.caustics_only != 0.0) {
        bool mirror = m.metallic > 0.5 && m.roughness < kCausticMirrorRoughness;
        if (p.caustic_phase >= 1 && !mirror) return true;  // a second diffuse vertex: no caustic
        if (p.caustic_phase == 1) p.caustic_phase = 2;
        // The first diffuse vertex's own direct light is no caustic; its light through glass or
        // off a mirror, found from here on, is. A mirror before it is the camera's view.
        if (p.caustic_phase == 0 && !mirror) p.caustic_phase = 1;
    }
    if (counted(p)) {
        if (other_light(p)) p.sum += p.throughput * direct_punctual(s, m, v);
#ifdef HAS_EMITTERS
        p.sum += p.throughput * direct_emitters(s, m, v, p.rng, true);
#endif
    }
#ifdef HAS_ENV_MAP_SAMPLING
    if (other_light(p)) {
        float pdf_env;
        vec3 le = sample_env(p.rng, pdf_env);
        vec3 fc = pdf_env > 0.0 ? brdf_cos_folded(m, s, le, v) : vec3(0.0);
        if (max(fc.r, max(fc.g, fc.b)) > 0.0 &&
            !trace_any(make_ray(offset_ray(s.p, s.ng, rt.ray_offset), le), 3.0e38)) {
            float w = power_heuristic(pdf_env, brdf_pdf_folded(m, s, v, le));
            p.sum += p.throughput * fc * environment(le) * w / pdf_env;
        }
    }
#endif
    vec3 l;
    if (!sample_brdf_folded(m, s, v, p.rng, l)) return true;
    float pdf = brdf_pdf_folded(m, s, v, l);
    if (pdf <= 0.0) return true;
    p.throughput *= brdf_cos_folded(m, s, l, v) / pdf;
    p.last_brdf_pdf = pdf;
    if (p.depth >= 3) {
        float survive = clamp(max(p.throughput.r, max(p.throughput.g, p.throughput.b)), 0.05, 0.95);
        if (rng_next(p.rng) >= survive) return true;
        p.throughput /= survive;
    }
    p.ray = make_ray(offset_ray(s.p, s.ng, rt.ray_offset), l);
    return ++p.depth > max_depth;
}

void main() {
    ivec2 pixel = dispatch_pixel();
    if (pixel.x >= rt.width || pixel.y >= rt.height) return;
    uint index = uint(pixel.y * rt.width + pixel.x);
    int count = dispatch_samples(), stride = dispatch_sample_stride();
    vec3 total = vec3(0.0);
    int k = 0;
    PathState p = path_start(pixel, index, uint(rt.sample_index));
    while (true) {
        if (!path_step(p)) continue;
        total += checked_sample(p.sum);
        if (++k == count) break;
        p = path_start(pixel, index, uint(rt.sample_index + k * stride));
    }
    accumulate(index, total, count);
}
