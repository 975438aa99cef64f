#version 450 core
// GI probes, step 2 of an update (engine/effects/gi/gi.cpp): work groups (probe of the batch,
// 64 texels of the probe's two tiles). Each invocation sums the probe's rays for its texel: irradiance E(n) = pi * sum(L cos+) / sum(cos+)
// over the ray directions (uniform on the sphere), and the first two moments of the hit distance
// weighted by cos^50 (Majercik et al. 2019). The new estimate is blended with the stored one by
// gi.weight (1: replace). Border texels repeat the octahedral map across the tile's edges.
// Irradiance alpha: 1 for an active probe, 0 for one that sees back faces in more than a quarter
// of its rays (it is inside geometry).
#include "common/math.glsl"
#include "effects/gi/gi_sample.glsl"
layout(local_size_x = 64) in;
// The rays probe_trace.comp wrote (GiRays), as a buffer texture: texel fetches are what llvmpipe
// reads fastest.
layout(binding = GI_RAYS_UNIT) uniform samplerBuffer t_gi_rays;
layout(binding = GI_IRRADIANCE_IMAGE, rgba32f) uniform image2D i_irradiance;
layout(binding = GI_DEPTH_IMAGE, rg32f) uniform image2D i_depth;


// The interior texel a tile texel shows: itself, or for a border texel the one it repeats (the
// octahedral map folds each edge onto itself, mirrored; a corner repeats the opposite corner).
ivec2 interior_texel(ivec2 t, int n) {
    bool left = t.x == 0, right = t.x == n + 1, top = t.y == 0, bottom = t.y == n + 1;
    if ((left || right) && (top || bottom)) return ivec2(left ? n : 1, top ? n : 1);
    if (top || bottom) return ivec2(n + 1 - t.x, top ? 1 : n);
    if (left || right) return ivec2(left ? 1 : n, n + 1 - t.y);
    return t;
}

void main() {
    int total = gi.probe_counts.x * gi.probe_counts.y * gi.probe_counts.z;
    int probe = gi.first_probe + int(gl_WorkGroupID.x);
    if (probe >= total) return;  // the whole group
    ivec3 c = gi_probe_coord(probe);
    ivec2 tile_index = ivec2(c.x + c.z * gi.probe_counts.x, c.y);
    int ni = gi.irradiance_texels, nd = gi.depth_texels;
    int irr_side = ni + 2, depth_side = nd + 2;
    int irr_texels = irr_side * irr_side;
    int count = irr_texels + depth_side * depth_side;
    int lid = int(gl_LocalInvocationIndex);
    int idx = int(gl_WorkGroupID.y) * 64 + lid;  // this invocation's texel of the probe's two tiles
    bool irr = idx < irr_texels;
    int local = irr ? idx : idx - irr_texels;
    int side = irr ? irr_side : depth_side;
    ivec2 t = interior_texel(ivec2(local % side, local / side), irr ? ni : nd);
    vec3 dir = gi_oct_decode((vec2(t) - 0.5) / float(irr ? ni : nd) * 2.0 - 1.0);
    vec4 acc = vec4(0.0);
    int rays = gi.rays_per_probe;
    int first = probe * rays;
    int back = 0;
    if (idx >= count) return;
    if (irr) {
        for (int r = 0; r < rays; ++r) {
            vec4 ray = texelFetch(t_gi_rays, 2 * (first + r));
            if (ray.a < 0.0) ++back;
            float x = max(dot(dir, texelFetch(t_gi_rays, 2 * (first + r) + 1).xyz), 0.0);
            acc += vec4(ray.rgb * x, x);
        }
    } else {
        for (int r = 0; r < rays; ++r) {
            float dist = abs(texelFetch(t_gi_rays, 2 * (first + r)).a);
            // cos^50 (DDGI's distance sharpness) by squaring: x^50 = x^32 x^16 x^2.
            float x = max(dot(dir, texelFetch(t_gi_rays, 2 * (first + r) + 1).xyz), 0.0);
            float x2 = x * x, x4 = x2 * x2, x8 = x4 * x4, x16 = x8 * x8, x32 = x16 * x16;
            float w = x32 * x16 * x2;
            acc += vec4(w * dist, w * dist * dist, w, 0.0);
        }
    }
    float alpha = gi.weight;
    if (irr) {
        ivec2 texel = tile_index * irr_side + ivec2(local % irr_side, local / irr_side);
        vec3 E = acc.w > 0.0 ? PI * acc.rgb / acc.w : vec3(0.0);
        vec4 old = imageLoad(i_irradiance, texel);
        imageStore(i_irradiance, texel, vec4(mix(old.rgb, E, alpha), float(back * 4 <= rays)));
    } else {
        ivec2 texel = tile_index * depth_side + ivec2(local % depth_side, local / depth_side);
        vec2 m = acc.z > 0.0 ? acc.xy / acc.z : vec2(gi.miss_distance, gi.miss_distance * gi.miss_distance);
        vec4 old = imageLoad(i_depth, texel);
        imageStore(i_depth, texel, vec4(mix(old.rg, m, alpha), 0.0, 0.0));
    }
}
