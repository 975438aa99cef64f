// What every tracer mode shares (shaders/rt/modes/*.comp, one compute program per mode): the
// scene and its traversal, the diagnostic counters, the accumulation buffer, the environment
// lookup, camera rays, and main(), which traces one sample per pixel per dispatch and adds it to
// `accum`. A mode file includes this first and defines radiance(), the light one camera ray
// brings back. Scene features are compiled in only when the scene has them (defines set by
// engine/rt/ray_tracer.cpp): HAS_EMITTERS (emissive triangles and spheres), HAS_TRANSMISSION
// (KHR_materials_transmission), HAS_BLEND (alphaMode BLEND: layers composited along camera rays),
// HAS_MASK (alphaMode MASK: every ray tests the cutoff at candidate hits), HAS_ENV_MAP_SAMPLING
// (path: environment map importance sampling), RT_STATS (traversal counters); and for what the
// scene lacks: RT_NO_TEXTURES (no material has a texture), RT_NO_SPHERES (no sphere primitives).
// llvmpipe runs both sides of a branch for its 8 SIMD lanes, masked, so code a scene never
// takes still costs every bounce unless it is compiled out: without the texture reads the
// Cornell box's path program runs 1.3x faster.
#ifdef RT_STATS
// Lane utilisation: one lane per subgroup counts each traversal step (see scene.glsl).
#extension GL_ARB_gpu_shader_int64 : enable
#extension GL_ARB_shader_ballot : enable
#endif
#define LIGHTS_UNBOUNDED  // the tracer keeps every light's whole reach (lights.glsl)
#include "../common/scene_data.glsl"
#include "../common/brdf.glsl"
#include "../common/sampling.glsl"
layout(std430, binding = RT_DIAGNOSTICS_BINDING) buffer Diagnostics {
    uint nonfinite_samples;
    uint traversal_nodes;      // RT_STATS only: BVH nodes visited, all rays
    uint traversal_primitives; // RT_STATS only: primitives intersected, all rays
    uint traversal_rays;       // RT_STATS only
    uint traversal_lane_slots; // RT_STATS only: the subgroup's size, summed over its traversal steps
};
layout(local_size_x = 8, local_size_y = 8) in;  // before scene.glsl: its traversal stacks are sized by it
#include "scene.glsl"

layout(std430, binding = RT_ACCUM_BINDING) buffer Accum { vec4 accum[]; };  // rgb sum, w sample count
layout(binding = ENVIRONMENT_UNIT) uniform sampler2D t_environment;

vec3 environment(vec3 dir) {
    if (rt.env_map_bound < 0.5) return rt.env_radiance.rgb;
    return rt.env_radiance.rgb * textureLod(t_environment, direction_to_equirect(normalize(dir)), 0.0).rgb;
}

Ray make_ray(vec3 origin, vec3 dir) {
    Ray r;
    r.origin = origin;
    r.dir = dir;
    return r;
}

#ifndef RT_NO_CAMERA  // programs that trace from elsewhere (the GI probes) have their own main()
// ---- camera ------------------------------------------------------------------------------------

// A point uniform over the unit disk by area: Shirley & Chiu's concentric map (1997), which
// preserves area, so uniform squares map to uniform disk points.
vec2 sample_uniform_disk(vec2 u) {
    vec2 o = 2.0 * u - 1.0;
    if (o.x == 0.0 && o.y == 0.0) return vec2(0.0);
    float r, theta;
    if (abs(o.x) > abs(o.y)) {
        r = o.x;
        theta = 0.78539816 * (o.y / o.x);
    } else {
        r = o.y;
        theta = 1.57079633 - 0.78539816 * (o.x / o.y);
    }
    return r * vec2(cos(theta), sin(theta));
}

// The camera ray through a random point of the pixel (or its centre without jitter); with a thin
// lens (rt.lens_x.w > 0: perspective cameras only), from a random point of the lens. `index`
// and `sample_index` are the pixel's and the sample's, for the lens's random stream.
Ray camera_ray(ivec2 pixel, uint index, uint sample_index, inout Rng rng) {
    vec2 jitter = rt.jitter != 0 ? vec2(rng_next(rng), rng_next(rng)) : vec2(0.5);
    vec2 ndc = vec2((float(pixel.x) + jitter.x) / float(rt.width) * 2.0 - 1.0,
                    1.0 - (float(pixel.y) + jitter.y) / float(rt.height) * 2.0);
    vec4 far_point = rt.inv_view_proj * vec4(ndc, 0.5, 1.0);
    vec4 near_point = rt.inv_view_proj * vec4(ndc, 1.0, 1.0);
    vec3 a = near_point.xyz / near_point.w;
    vec3 b = far_point.xyz / far_point.w;
    // Perspective: rays from the camera position; orthographic: from the near plane. The points
    // are relative to the camera, so precision does not depend on where the camera is.
    Ray r;
    r.origin = rt.camera_pos.xyz + a;
    r.dir = normalize(b - a);
    if (rt.lens_x.w > 0.0) {
        // Thin lens (Cook, Porter & Carpenter 1984; PBRT 3rd ed. 6.2.3): a point uniform over
        // the lens disk, aimed at this ray's point on the focal plane (the plane at the focus
        // distance along the view axis), so that points on that plane stay sharp and others
        // blur into a circle of diameter 2 A |d - F| / d there. Its own random stream: the
        // pixel jitter and the mode's samples are those of the pinhole image.
        Rng lens_rng = rng_init(pcg_hash(uint(rt.seed) ^ 0x6c656e73u), index, sample_index);
        vec2 u = sample_uniform_disk(vec2(rng_next(lens_rng), rng_next(lens_rng)));
        vec3 axis = rt.lens_axis.xyz;
        vec3 focus = r.dir * (rt.lens_y.w / dot(r.dir, axis));  // camera-relative
        vec3 lens = u.x * rt.lens_x.xyz + u.y * rt.lens_y.xyz;
        r.dir = normalize(focus - lens);
        // From the near plane, as the pinhole ray: nothing nearer than znear is seen.
        r.origin = rt.camera_pos.xyz + lens + r.dir * (dot(a, axis) / dot(r.dir, axis));
    }
    return r;
}

// The samples of one dispatch: rt.dispatch_samples samples per pixel (0 counts as 1), the k-th being
// sample rt.sample_index + k * stride, stride = rt.sample_stride (--spp-shard's N; 0 counts as 1). Each
// sample's random stream depends on (seed, pixel, sample index) only, so how samples are grouped
// into dispatches does not change them.
int dispatch_samples() { return max(rt.dispatch_samples, 1); }
int dispatch_sample_stride() { return max(int(rt.sample_stride), 1); }
ivec2 dispatch_pixel() { return ivec2(gl_GlobalInvocationID.xy) + ivec2(0, rt.tile_y); }

// Adds a dispatch's samples of a pixel (their radiance sum) to the accumulation buffer; a
// non-finite sample is counted and replaced by 0 (checked_sample).
void accumulate(uint index, vec3 sum, int count) { accum[index] += vec4(sum, float(count)); }
vec3 checked_sample(vec3 L) {
    if (any(isnan(L)) || any(isinf(L))) {
        atomicAdd(nonfinite_samples, 1u);
        return vec3(0.0);
    }
    return L;
}

#ifndef RT_OWN_MAIN  // a mode may schedule its samples itself (path.comp)
// The mode's estimate of the radiance arriving along a camera ray (defined by each mode file).
vec3 radiance(Ray ray, inout Rng rng);

void main() {
    ivec2 pixel = dispatch_pixel();
    if (pixel.x >= rt.width || pixel.y >= rt.height) return;
    uint index = uint(pixel.y * rt.width + pixel.x);
    int count = dispatch_samples(), stride = dispatch_sample_stride();
    vec3 sum = vec3(0.0);
    for (int k = 0; k < count; ++k) {
        uint sample_index = uint(rt.sample_index + k * stride);
        Rng rng = rng_init(uint(rt.seed), index, sample_index);
        Ray ray = camera_ray(pixel, index, sample_index, rng);
        sum += checked_sample(radiance(ray, rng));
    }
    accumulate(index, sum, count);
}
#endif  // RT_OWN_MAIN
#endif  // RT_NO_CAMERA
