// What every tracer mode shares (shaders/rt/modes/*.comp, one compute program per mode): the
// scene and its traversal, the diagnostic counters, the accumulation buffer, the environment
// lookup, camera rays, and main(), which traces one sample per pixel per dispatch and adds it to
// `accum`. A mode file includes this first and defines radiance(), the light one camera ray
// brings back. Scene features are compiled in only when the scene has them (defines set by
// engine/rt/ray_tracer.cpp): HAS_EMITTERS (emissive triangles and spheres), HAS_TRANSMISSION
// (KHR_materials_transmission), HAS_BLEND (alphaMode BLEND: layers composited along camera rays),
// HAS_MASK (alphaMode MASK: every ray tests the cutoff at candidate hits), HAS_ENV_MAP_SAMPLING
// (path: environment map importance sampling), RT_STATS (traversal counters).
#include "../common/scene_data.glsl"
#include "../common/brdf.glsl"
#include "../common/sampling.glsl"
layout(std430, binding = 10) buffer Diagnostics {
    uint nonfinite_samples;
    uint traversal_nodes;      // RT_STATS only: BVH nodes visited, all rays
    uint traversal_primitives; // RT_STATS only: primitives intersected, all rays
    uint traversal_rays;       // RT_STATS only
};
layout(local_size_x = 8, local_size_y = 8) in;  // before scene.glsl: its traversal stacks are sized by it
#include "scene.glsl"

layout(std430, binding = 9) buffer Accum { vec4 accum[]; };  // rgb sum, w sample count
layout(binding = 5) uniform sampler2D t_environment;

vec3 environment(vec3 dir) {
    if (rt.env_radiance.w < 0.5) return rt.env_radiance.rgb;
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

Ray camera_ray(ivec2 pixel, inout Rng rng) {
    vec2 jitter = rt.params.y != 0 ? vec2(rng_next(rng), rng_next(rng)) : vec2(0.5);
    vec2 ndc = vec2((float(pixel.x) + jitter.x) / float(rt.image.x) * 2.0 - 1.0,
                    1.0 - (float(pixel.y) + jitter.y) / float(rt.image.y) * 2.0);
    vec4 far_point = rt.inv_view_proj * vec4(ndc, 0.5, 1.0);
    vec4 near_point = rt.inv_view_proj * vec4(ndc, 1.0, 1.0);
    vec3 a = near_point.xyz / near_point.w;
    vec3 b = far_point.xyz / far_point.w;
    // Perspective: rays from the camera position; orthographic: from the near plane. The points
    // are relative to the camera, so precision does not depend on where the camera is.
    Ray r;
    r.origin = rt.camera_pos.xyz + a;
    r.dir = normalize(b - a);
    return r;
}

// The mode's estimate of the radiance arriving along a camera ray (defined by each mode file).
vec3 radiance(Ray ray, inout Rng rng);

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy) + ivec2(0, rt.params.w);
    if (pixel.x >= rt.image.x || pixel.y >= rt.image.y) return;
    uint index = uint(pixel.y * rt.image.x + pixel.x);
    Rng rng = rng_init(uint(rt.image.w), index, uint(rt.image.z));
    Ray ray = camera_ray(pixel, rng);
    vec3 L = radiance(ray, rng);
    if (any(isnan(L)) || any(isinf(L))) {
        atomicAdd(nonfinite_samples, 1u);
        L = vec3(0.0);
    }
    accum[index] += vec4(L, 1.0);
}
#endif
