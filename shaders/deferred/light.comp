#version 450 core
// Tiled deferred lighting (Andersson 2011, "DirectX 11 Rendering in Battlefield 3"): one 16x16
// workgroup per screen tile finds the tile's depth range, culls the light list against the tile's
// sub-frustum (point and spot lights by their reach, common/lights.glsl light_reach; unbounded
// lights always pass), then shades
// its pixels from the G-buffer with only the lights that survived. Adds to the light buffer,
// which already holds the emission.
//
// MULTISAMPLED (anti-aliasing, engine/effects/aa): the G-buffer, depth and light buffer have N
// samples per pixel. The samples of a pixel are grouped by the surface they see (differs()
// below); each group is shaded once, at the mean of its samples' positions with the mean of
// their depths (for one plane that is the depth there: NDC depth is affine in screen space), and
// the result is added to each of its samples. A pixel whose samples all see one surface (all but
// a few percent) is one group shaded at the pixel centre, as forward multisampling shades a
// fragment; an edge pixel gets one shading per surface it shows (what shading every sample
// would give, up to the position inside the pixel, and usually 2 shadings instead of N).
#include "../common/scene_data.glsl"
#include "../lighting/gbuffer.glsl"
#include "../lighting/shading.glsl"
#include "../lighting/tile_frustum.glsl"

#ifdef EDGE_GROUPS
layout(local_size_x = 64) in;
#else
layout(local_size_x = 16, local_size_y = 16) in;
#endif

#ifdef MULTISAMPLED
layout(binding = GBUFFER_BASE_UNIT) uniform sampler2DMS g_base_occlusion;
layout(binding = GBUFFER_NORMAL_UNIT) uniform sampler2DMS g_normal_rm;
layout(binding = GBUFFER_F0_UNIT) uniform sampler2DMS g_f0_f90;
layout(binding = GBUFFER_DEPTH_UNIT) uniform sampler2DMS g_depth;
layout(rgba32f, binding = LIGHT_BUFFER_IMAGE) uniform image2DMS light_buffer;
layout(location = 0) uniform int u_count_edges;    // 1: count into AaEdgeStats (a debug readback)
layout(location = 1) uniform vec2 u_sample_pos[8];  // sample positions in the pixel, [0,1], y up
layout(std430, binding = AA_EDGE_STATS_BINDING) buffer AaEdgeStats {
    uint edge_pixels;      // pixels shaded more than once (samples on two or more surfaces)
    uint geometry_pixels;  // pixels with geometry in at least one sample
    uint shadings;         // surface groups shaded, over all pixels
};
const int kMaxSamples = 8;
// The sample groups of the edge pixels beyond each pixel's first (x | y << 16, sample mask),
// appended by the tiled pass and shaded by the EDGE_GROUPS pass, one invocation each: shading
// them in the tiled pass, in a loop or at a second call site, made llvmpipe's whole pass about
// 1.8x slower on generated:edges although they are 1.5 % of the shadings; here they cost what
// they shade. EdgeDispatch is also the indirect dispatch's arguments.
layout(rg32ui, binding = EDGE_GROUPS_IMAGE) uniform uimage2D edge_groups;
layout(std430, binding = EDGE_DISPATCH_BINDING) buffer EdgeDispatch {
    uint edge_workgroups;     // ceil(edge_entries / 64)
    uint edge_workgroups_y;   // 1
    uint edge_workgroups_z;   // 1
    uint edge_entries;
};
#else
layout(binding = GBUFFER_BASE_UNIT) uniform sampler2D g_base_occlusion;
layout(binding = GBUFFER_NORMAL_UNIT) uniform sampler2D g_normal_rm;
layout(binding = GBUFFER_F0_UNIT) uniform sampler2D g_f0_f90;
layout(binding = GBUFFER_DEPTH_UNIT) uniform sampler2D g_depth;
layout(rgba32f, binding = LIGHT_BUFFER_IMAGE) uniform image2D light_buffer;
#endif

// The tile's lights as a bit set, so that they are summed in index order, as the forward pass
// does (a deterministic image, equal to forward's up to G-buffer precision). More lights than
// the set holds: every tile shades all of them.
const int kMaxTiledLights = 2048;
shared uint s_depth_min, s_depth_max;
shared uint s_mask[kMaxTiledLights / 32];
shared vec4 s_planes[4];
shared vec2 s_zrange;  // view-space z of the tile's far and near ends (negative)

// Conservative: a sphere that misses the tile's sub-frustum is dropped.
bool light_in_tile(LightData light) {
    int type = int(light.type);
    float reach = light_reach(light);
    if ((type == LIGHT_POINT || type == LIGHT_SPOT) && reach > 0.0) {
        float z = (frame.view * vec4(light.position, 1.0)).z;
        if (z - reach > s_zrange.y || z + reach < s_zrange.x) return false;
    }
    return light_meets_planes(light, s_planes);
}

// Adds the light reflected at p towards v to `color` (the emission already there), in the order
// the forward pass sums it. `light_count` lights; `tiled`: only those in the tile's mask.
vec3 shade_surface(vec3 color, BrdfInput bi, float occlusion, vec3 p, vec3 n, vec3 v, vec2 pixel, int light_count, bool tiled) {
    if (!tiled) {
        for (int i = 0; i < light_count; ++i) color += shade_light(i, bi, p, n, v, pixel);
    } else {
        for (int w = 0; w < (light_count + 31) / 32; ++w) {
            uint bits = s_mask[w];
            while (bits != 0u) {
                int b = findLSB(bits);
                bits &= bits - 1u;
                color += shade_light(w * 32 + b, bi, p, n, v, pixel);
            }
        }
    }
    effect_add_direct_light(color, bi, p, n, v, pixel, 0.0);
    color += shade_ambient(bi, p, n, v, occlusion * effect_occlusion(pixel));
    effect_add_indirect_light(color, bi, p, n, v, pixel, occlusion, 0.0);
    return color;
}

vec3 world_point(vec2 ndc, float depth) {
    vec4 pw = frame.inv_view_proj * vec4(ndc, depth, 1.0);
    return pw.xyz / pw.w;
}

#ifdef MULTISAMPLED
// What the grouping compares of one sample.
struct GSample {
    vec4 base, nrm, f0;  // G-buffer attachments 0-2
    vec3 n;              // decoded normal
    float dist;          // view depth (distance from the camera plane)
    float tol;           // how far the depth may differ on one surface
};

// The view depth of a stored depth: reversed-Z, perspective (finite or infinite far plane) or
// orthographic; frame.proj's z row (the sub-frames shift x and y only).
float view_depth(float d) {
    float p22 = frame.proj[2][2], p32 = frame.proj[3][2];
    return frame.proj[3][3] == 0.0 ? p32 / (d + p22) : (p32 - d) / p22;
}

// `v`: towards the camera from the pixel's surface; `pixel_angle`: a pixel's width at view depth
// 1 (perspective) or in scene units (orthographic).
GSample g_sample(ivec2 q, int s, vec3 v, float pixel_angle) {
    GSample g;
    g.base = texelFetch(g_base_occlusion, q, s);
    g.nrm = texelFetch(g_normal_rm, q, s);
    g.f0 = texelFetch(g_f0_f90, q, s);
    g.n = oct_decode(g.nrm.xy);
    g.dist = view_depth(texelFetch(g_depth, q, s).r);
    // 1 %, plus what a plane seen at angle theta changes across the samples (within 0.75 pixel
    // of each other): footprint x tan(theta), tan capped at 85 degrees.
    float c = clamp(abs(dot(g.n, v)), 0.087, 1.0);
    float footprint = frame.proj[3][3] == 0.0 ? g.dist * pixel_angle : pixel_angle;
    g.tol = 0.01 * g.dist + 1.5 * footprint * sqrt(1.0 - c * c) / c;
    return g;
}

// Whether two samples see different surfaces. Attributes: what the shading reads, with
// tolerances below which one shading serves both (one sRGB 8-bit step of base colour is
// ~0.4-1 %; 5.7 degrees of normal). Depth: their distances from the camera differ by more than
// 1 % plus what a's slope allows across the pixel (view depths: for samples this close, the
// same ratio as distances along their rays); this separates an object from what is behind
// it even where both have the same material and normal. Samples of one fragment hold bit-equal
// attributes, so the interior of every triangle is one group; so are pixels where two triangles
// of one smooth mesh meet, unless their values differ by more than the tolerances.
bool differs(GSample a, GSample b) {
    if (any(greaterThan(abs(b.base.rgb - a.base.rgb), vec3(3.5 / 255.0))) || abs(b.base.a - a.base.a) > 0.02) return true;
    if (any(greaterThan(abs(b.nrm.zw - a.nrm.zw), vec2(0.02)))) return true;
    if (any(greaterThan(abs(b.f0 - a.f0), vec4(0.004)))) return true;
    if (b.nrm.xy != a.nrm.xy && dot(b.n, a.n) < 0.995) return true;
    return abs(b.dist - a.dist) > a.tol;
}

// The light buffer value of a group of samples (bit mask `m`) of pixel q seeing one surface:
// shaded at the mean of their positions and depths, with the attributes of the first.
void shade_group(ivec2 q, uint m, int light_count, bool tiled, vec2 px_ndc) {
    int first = findLSB(m);
    vec2 offset = vec2(0.0);
    float depth = 0.0, k = 0.0;
    for (int s = first; s < kMaxSamples; ++s)
        if ((m & (1u << uint(s))) != 0u) {
            offset += u_sample_pos[s] - 0.5;
            depth += texelFetch(g_depth, q, s).r;
            k += 1.0;
        }
    vec2 pixel = vec2(q) + 0.5;  // screen buffers (SSAO, RSM) and shadow noise: per pixel
    vec3 p = world_point(pixel * px_ndc - 1.0 + offset / k * px_ndc, depth / k);
    vec4 base_occlusion = texelFetch(g_base_occlusion, q, first);
    vec4 normal_rm = texelFetch(g_normal_rm, q, first);
    BrdfInput bi = gbuffer_brdf(base_occlusion, normal_rm, texelFetch(g_f0_f90, q, first));
    vec3 n = oct_decode(normal_rm.xy);
    vec3 v = normalize(frame.camera_pos.xyz - p);
    vec3 lit;
#ifndef NO_DEBUG_VIEW
    if (frame.debug_view == DEBUG_VIEW_INDIRECT) {
        lit = vec3(0.0);
        effect_add_indirect_light(lit, bi, p, n, v, pixel, base_occlusion.a, 0.0);
    } else if (frame.debug_view != DEBUG_VIEW_NONE) {
        lit = vec3(frame.debug_view == DEBUG_VIEW_VISIBILITY ? light_visibility(p, n, pixel) : effect_occlusion(pixel));
    } else
#endif
    lit = shade_surface(vec3(0.0), bi, base_occlusion.a, p, n, v, pixel, light_count, tiled);
    for (int s = first; s < kMaxSamples; ++s)
        if ((m & (1u << uint(s))) != 0u) {
            vec3 emission = imageLoad(light_buffer, q, s).rgb;
            imageStore(light_buffer, q, s, vec4(frame.debug_view != DEBUG_VIEW_NONE ? lit : emission + lit, 1.0));
        }
}
#endif

#ifdef EDGE_GROUPS
// The edge pixels' further sample groups (the tiled pass listed them), all lights untiled.
void main() {
    uint k = gl_GlobalInvocationID.x;
    ivec2 list_size = imageSize(edge_groups);
    if (k >= min(edge_entries, uint(list_size.x * list_size.y))) return;
    uvec2 e = imageLoad(edge_groups, ivec2(int(k) % list_size.x, int(k) / list_size.x)).xy;
    ivec2 q = ivec2(int(e.x & 0xffffu), int(e.x >> 16));
    shade_group(q, e.y, effect_shaded_light_count(), false, 2.0 / vec2(imageSize(light_buffer)));
}
#else
void main() {
    ivec2 size = imageSize(light_buffer);
    ivec2 gid = ivec2(gl_GlobalInvocationID.xy);
    uint local = gl_LocalInvocationIndex;
    bool inside = all(lessThan(gid, size));
#ifdef MULTISAMPLED
    // The pixel's samples: which have geometry, their depth range for the tile.
    int samples = min(textureSamples(g_depth), kMaxSamples);
    uint covered_mask = 0u;
    float depth_lo = 3.4e38, depth_hi = 0.0;
    int covered = 0;
    for (int s = 0; s < samples; ++s) {
        float d = inside ? texelFetch(g_depth, gid, s).r : 0.0;
        if (d > 0.0) {
            depth_lo = min(depth_lo, d);
            depth_hi = max(depth_hi, d);
            covered_mask |= 1u << uint(s);
            ++covered;
        }
    }
    bool geometry = covered > 0;
#else
    float depth = inside ? texelFetch(g_depth, gid, 0).r : 0.0;
    bool geometry = inside && depth > 0.0;  // reversed-Z: cleared to 0 where nothing was drawn
#endif

    if (local == 0u) {
        s_depth_min = 0x7f7fffffu;
        s_depth_max = 0u;
    }
    if (local < uint(kMaxTiledLights / 32)) s_mask[local] = 0u;
    barrier();
    // Positive floats order like their bit patterns.
#ifdef MULTISAMPLED
    if (geometry) {
        atomicMin(s_depth_min, floatBitsToUint(depth_lo));
        atomicMax(s_depth_max, floatBitsToUint(depth_hi));
    }
#else
    if (geometry) {
        atomicMin(s_depth_min, floatBitsToUint(depth));
        atomicMax(s_depth_max, floatBitsToUint(depth));
    }
#endif
    barrier();
    bool any_geometry = s_depth_max > 0u;
    if (local == 0u && any_geometry) {
        mat4 inv_proj = inverse(frame.proj);
        vec2 lo = vec2(gl_WorkGroupID.xy * gl_WorkGroupSize.xy) / vec2(size) * 2.0 - 1.0;
        vec2 hi = vec2(min((gl_WorkGroupID.xy + 1u) * gl_WorkGroupSize.xy, uvec2(size))) / vec2(size) * 2.0 - 1.0;
        float dfar = uintBitsToFloat(s_depth_min), dnear = uintBitsToFloat(s_depth_max);
        vec4 planes[4];
        vec2 zrange;
        tile_frustum(inv_proj, lo, hi, dnear, dfar, planes, zrange);
        for (int i = 0; i < 4; ++i) s_planes[i] = planes[i];
        s_zrange = zrange;
    }
    barrier();
    // The lights shaded one by one (with LTC area lights: the punctual ones; the polygons follow).
    int light_count = effect_shaded_light_count();
    bool tiled = light_count <= kMaxTiledLights;
    if (any_geometry && tiled) {
        for (int i = int(local); i < light_count; i += 256)
            if (light_in_tile(lights[i])) atomicOr(s_mask[i >> 5], 1u << uint(i & 31));
    }
    barrier();
#ifdef MULTISAMPLED
    // The pixel's samples grouped by surface (background samples in none: the sky pass fills
    // them). The first group is shaded here, by every invocation at once; the others are listed
    // and shared out over the workgroup, so that the few edge pixels do not keep every SIMD batch
    // they fall in looping (Lauritzen 2010, "Deferred Rendering for Current and Future Rendering
    // Pipelines": per-sample work redistributed over the tile).
    vec2 px_ndc = 2.0 / vec2(size);
    vec2 centre_ndc = (vec2(gid) + 0.5) * px_ndc - 1.0;
    float pixel_angle = 2.0 / (float(size.y) * abs(frame.proj[1][1]));
    vec3 v_pixel = normalize(frame.camera_pos.xyz - world_point(centre_ndc, depth_hi));
    if (frame.proj[3][3] != 0.0) v_pixel = vec3(frame.view[0][2], frame.view[1][2], frame.view[2][2]);  // orthographic: the view axis
    uint rest = covered_mask, first_group = 0u;
    int group_count = 0;
    while (rest != 0u) {
        int t = findLSB(rest);
        GSample a = g_sample(gid, t, v_pixel, pixel_angle);
        uint m = 1u << uint(t);
        for (int s = t + 1; s < samples; ++s)
            if ((rest & (1u << uint(s))) != 0u && !differs(a, g_sample(gid, s, v_pixel, pixel_angle))) m |= 1u << uint(s);
        rest &= ~m;
        if (group_count == 0) first_group = m;
        else {
            uint k = atomicAdd(edge_entries, 1u);
            if (k % 64u == 0u) atomicAdd(edge_workgroups, 1u);
            ivec2 list_size = imageSize(edge_groups);
            if (k < uint(list_size.x * list_size.y))  // sized for N - 1 per pixel: never full
                imageStore(edge_groups, ivec2(int(k) % list_size.x, int(k) / list_size.x), uvec4(uint(gid.x) | (uint(gid.y) << 16), m, 0u, 0u));
        }
        ++group_count;
    }
    if (geometry && u_count_edges != 0) {
        atomicAdd(geometry_pixels, 1u);
        if (group_count > 1) atomicAdd(edge_pixels, 1u);
        atomicAdd(shadings, uint(group_count));
    }
    if (first_group != 0u) shade_group(gid, first_group, light_count, tiled, px_ndc);
#else
    if (!geometry) return;
    vec4 base_occlusion = texelFetch(g_base_occlusion, gid, 0);
    vec4 normal_rm = texelFetch(g_normal_rm, gid, 0);
    BrdfInput bi = gbuffer_brdf(base_occlusion, normal_rm, texelFetch(g_f0_f90, gid, 0));
    vec3 n = oct_decode(normal_rm.xy);
    vec2 ndc = (vec2(gid) + 0.5) / vec2(size) * 2.0 - 1.0;
    vec3 p = world_point(ndc, depth);
    vec3 v = normalize(frame.camera_pos.xyz - p);
    vec2 pixel = vec2(gid) + 0.5;
#ifndef NO_DEBUG_VIEW
    if (frame.debug_view == DEBUG_VIEW_INDIRECT) {
        vec3 indirect = vec3(0.0);
        effect_add_indirect_light(indirect, bi, p, n, v, pixel, base_occlusion.a, 0.0);
        imageStore(light_buffer, gid, vec4(indirect, 1.0));
        return;
    }
    if (frame.debug_view != DEBUG_VIEW_NONE) {
        float value = frame.debug_view == DEBUG_VIEW_VISIBILITY ? light_visibility(p, n, pixel) : effect_occlusion(pixel);
        imageStore(light_buffer, gid, vec4(vec3(value), 1.0));
        return;
    }
#endif
    vec3 color = shade_surface(imageLoad(light_buffer, gid).rgb, bi, base_occlusion.a, p, n, v, pixel, light_count, tiled);
    imageStore(light_buffer, gid, vec4(color, 1.0));
#endif
}
#endif  // EDGE_GROUPS
