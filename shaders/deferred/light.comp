#version 450 core
// Tiled deferred lighting (Andersson 2011, "DirectX 11 Rendering in Battlefield 3"): one 16x16
// workgroup per screen tile finds the tile's depth range, culls the light list against the tile's
// sub-frustum (range-limited point and spot lights; unbounded lights always pass), then shades
// its pixels from the G-buffer with only the lights that survived. Adds to the light buffer,
// which already holds the emission.
//
// MULTISAMPLED (anti-aliasing, engine/effects/aa): the G-buffer, depth and light buffer have N
// samples per pixel. A pixel whose samples all see the same surface (edge_pixel() below) is
// shaded once, at the pixel centre with the mean of its sample depths (for one plane that is the
// depth at the centre: NDC depth is affine in screen space and the sample pattern is centred),
// and the result is added to every sample; an edge pixel is shaded once per sample, at the
// sample's own position and with its own G-buffer values.
#include "../common/scene_data.glsl"
#include "../lighting/gbuffer.glsl"
#include "../lighting/shading.glsl"

layout(local_size_x = 16, local_size_y = 16) in;

#ifdef MULTISAMPLED
layout(binding = 0) uniform sampler2DMS g_base_occlusion;
layout(binding = 1) uniform sampler2DMS g_normal_rm;
layout(binding = 2) uniform sampler2DMS g_f0_f90;
layout(binding = 3) uniform sampler2DMS g_depth;
layout(rgba32f, binding = 0) uniform image2DMS light_buffer;
layout(location = 0) uniform int u_count_edges;    // 1: count into AaEdgeStats (a debug readback)
layout(location = 1) uniform vec2 u_sample_pos[8];  // sample positions in the pixel, [0,1], y up
layout(std430, binding = 14) buffer AaEdgeStats {
    uint edge_pixels;      // pixels shaded per sample
    uint geometry_pixels;  // pixels with geometry in at least one sample
};
const int kMaxSamples = 8;
#else
layout(binding = 0) uniform sampler2D g_base_occlusion;
layout(binding = 1) uniform sampler2D g_normal_rm;
layout(binding = 2) uniform sampler2D g_f0_f90;
layout(binding = 3) uniform sampler2D g_depth;
layout(rgba32f, binding = 0) uniform image2D light_buffer;
#endif

// The tile's lights as a bit set, so that they are summed in index order, as the forward pass
// does (a deterministic image, equal to forward's up to G-buffer precision). More lights than
// the set holds: every tile shades all of them.
const int kMaxTiledLights = 2048;
shared uint s_depth_min, s_depth_max;
shared uint s_mask[kMaxTiledLights / 32];
shared vec4 s_planes[4];
shared vec2 s_zrange;  // view-space z of the tile's far and near ends (negative)

vec3 view_point(mat4 inv_proj, vec2 ndc, float depth) {
    vec4 p = inv_proj * vec4(ndc, depth, 1.0);
    return p.xyz / p.w;
}

// Conservative: a sphere that misses the tile's sub-frustum is dropped.
bool light_in_tile(PunctualLight light) {
    int type = int(light.position_type.w);
    float range = light.direction_range.w;
    if ((type != LIGHT_POINT && type != LIGHT_SPOT) || range <= 0.0) return true;
    vec3 c = (frame.view * vec4(light.position_type.xyz, 1.0)).xyz;
    if (c.z - range > s_zrange.y || c.z + range < s_zrange.x) return false;
    for (int i = 0; i < 4; ++i)
        if (dot(s_planes[i].xyz, c) + s_planes[i].w < -range) return false;
    return true;
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
    color += shade_area_lights(bi, p, n, v, pixel, 0.0);
    color += shade_ambient(bi, p, n, v, occlusion * ssao_at(pixel));
    color += rsm_indirect(bi, pixel, p);
    color += shade_gi(bi, p, n, v, occlusion, 0.0);
    return color;
}

vec3 world_point(vec2 ndc, float depth) {
    vec4 pw = frame.inv_view_proj * vec4(ndc, depth, 1.0);
    return pw.xyz / pw.w;
}

#ifdef MULTISAMPLED
// Whether sample s sees another surface than sample 0 (same test both ways). Attributes: what
// the shading reads, with tolerances below which shading once is indistinguishable (one sRGB
// 8-bit step of base colour is ~0.4-1 %; 5.7 degrees of normal). Depth: the samples' distances
// from the camera differ by more than 1 % plus what the surface's slope allows across the pixel
// (a plane seen at angle theta changes its distance by dist * pixel angle * tan(theta) per
// pixel): it separates an object from what is behind it even where both have the same
// material and normal. Samples of one fragment hold bit-equal attributes, so the interior of
// every triangle passes; pixels where two triangles of one smooth mesh meet pass too unless
// their values differ by more than the tolerances.
bool differs(int s, vec4 base0, vec4 nrm0, vec4 f00, float dist0, float slope_tol, vec3 n0, vec2 centre_ndc, vec2 px_ndc) {
    vec4 base = texelFetch(g_base_occlusion, ivec2(gl_GlobalInvocationID.xy), s);
    vec4 nrm = texelFetch(g_normal_rm, ivec2(gl_GlobalInvocationID.xy), s);
    vec4 f0 = texelFetch(g_f0_f90, ivec2(gl_GlobalInvocationID.xy), s);
    if (any(greaterThan(abs(base.rgb - base0.rgb), vec3(3.5 / 255.0))) || abs(base.a - base0.a) > 0.02) return true;
    if (any(greaterThan(abs(nrm.zw - nrm0.zw), vec2(0.02)))) return true;
    if (any(greaterThan(abs(f0 - f00), vec4(0.004)))) return true;
    if (nrm.xy != nrm0.xy && dot(oct_decode(nrm.xy), n0) < 0.995) return true;
    float depth = texelFetch(g_depth, ivec2(gl_GlobalInvocationID.xy), s).r;
    float dist = distance(world_point(centre_ndc + (u_sample_pos[s] - 0.5) * px_ndc, depth), frame.camera_pos.xyz);
    return abs(dist - dist0) > dist0 * (0.01 + slope_tol);
}
#endif

void main() {
    ivec2 size = imageSize(light_buffer);
    ivec2 gid = ivec2(gl_GlobalInvocationID.xy);
    uint local = gl_LocalInvocationIndex;
    bool inside = all(lessThan(gid, size));
#ifdef MULTISAMPLED
    // The pixel's samples: which have geometry, their depth range for the tile, their mean.
    int samples = min(textureSamples(g_depth), kMaxSamples);
    float sample_depth[kMaxSamples];
    float depth_lo = 3.4e38, depth_hi = 0.0, depth_sum = 0.0;
    int covered = 0;
    for (int s = 0; s < samples; ++s) {
        float d = inside ? texelFetch(g_depth, gid, s).r : 0.0;
        sample_depth[s] = d;
        if (d > 0.0) {
            depth_lo = min(depth_lo, d);
            depth_hi = max(depth_hi, d);
            depth_sum += d;
            ++covered;
        }
    }
    bool geometry = covered > 0;
    float depth = covered == samples ? depth_sum / float(samples) : depth_hi;
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
        vec3 n00 = view_point(inv_proj, lo, dnear), n10 = view_point(inv_proj, vec2(hi.x, lo.y), dnear);
        vec3 n01 = view_point(inv_proj, vec2(lo.x, hi.y), dnear), n11 = view_point(inv_proj, hi, dnear);
        vec3 f00 = view_point(inv_proj, lo, dfar), f10 = view_point(inv_proj, vec2(hi.x, lo.y), dfar);
        vec3 f01 = view_point(inv_proj, vec2(lo.x, hi.y), dfar), f11 = view_point(inv_proj, hi, dfar);
        vec3 centre = (n00 + n10 + n01 + n11 + f00 + f10 + f01 + f11) * 0.125;
        // Side planes through a near edge and the far point behind it; normals point inwards.
        vec3 a[4] = vec3[4](n00, n10, n11, n01);
        vec3 b[4] = vec3[4](n01, n00, n10, n11);
        vec3 f[4] = vec3[4](f00, f10, f11, f01);
        for (int i = 0; i < 4; ++i) {
            vec3 nrm = normalize(cross(b[i] - a[i], f[i] - a[i]));
            if (dot(nrm, centre - a[i]) < 0.0) nrm = -nrm;
            s_planes[i] = vec4(nrm, -dot(nrm, a[i]));
        }
        s_zrange = vec2(min(f00.z, min(f10.z, min(f01.z, f11.z))), max(n00.z, max(n10.z, max(n01.z, n11.z))));
    }
    barrier();
    // The lights shaded one by one (with LTC area lights: the punctual ones; the polygons follow).
    int light_count = shaded_light_count();
    bool tiled = light_count <= kMaxTiledLights;
    if (any_geometry && tiled) {
        for (int i = int(local); i < light_count; i += 256)
            if (light_in_tile(lights[i])) atomicOr(s_mask[i >> 5], 1u << uint(i & 31));
    }
    barrier();
    if (!geometry) return;

#ifdef MULTISAMPLED
    vec2 px_ndc = 2.0 / vec2(size);
    vec2 centre_ndc = (vec2(gid) + 0.5) * px_ndc - 1.0;
    vec2 pixel = vec2(gid) + 0.5;  // screen buffers (SSAO, RSM) and shadow noise: per pixel
    vec4 base0 = texelFetch(g_base_occlusion, gid, 0);
    vec4 nrm0 = texelFetch(g_normal_rm, gid, 0);
    vec4 f00 = texelFetch(g_f0_f90, gid, 0);
    vec3 n0 = oct_decode(nrm0.xy);
    bool edge = covered < samples;  // part background: the sky pass fills the rest per sample
    if (!edge) {
        vec3 p0 = world_point(centre_ndc + (u_sample_pos[0] - 0.5) * px_ndc, sample_depth[0]);
        float dist0 = distance(p0, frame.camera_pos.xyz);
        vec3 v0 = (frame.camera_pos.xyz - p0) / max(dist0, 1e-30);
        // The slope allowance: tan(theta) from the stored normal (capped: 85 degrees), pixel
        // angle from the projection (2 / (height * proj[1][1]) for a perspective camera).
        float c = clamp(abs(dot(n0, v0)), 0.087, 1.0);
        float slope_tol = 1.5 * (2.0 / (float(size.y) * abs(frame.proj[1][1]))) * sqrt(1.0 - c * c) / c;
        for (int s = 1; s < samples && !edge; ++s) edge = differs(s, base0, nrm0, f00, dist0, slope_tol, n0, centre_ndc, px_ndc);
    }
    if (u_count_edges != 0) {
        atomicAdd(geometry_pixels, 1u);
        if (edge) atomicAdd(edge_pixels, 1u);
    }
    if (!edge) {
        // One surface: shade once at the centre, add to every sample's emission.
        BrdfInput bi = gbuffer_brdf(base0, nrm0, f00);
        vec3 p = world_point(centre_ndc, depth);
        vec3 v = normalize(frame.camera_pos.xyz - p);
        if (frame.debug.x != 0) {
            vec3 value = frame.debug.x == 3 ? rsm_indirect(bi, pixel, p) + shade_gi(bi, p, n0, v, base0.a, 0.0)
                                            : vec3(frame.debug.x == 1 ? light_visibility(p, n0, pixel) : ssao_at(pixel));
            for (int s = 0; s < samples; ++s) imageStore(light_buffer, gid, s, vec4(value, 1.0));
            return;
        }
        vec3 lit = shade_surface(vec3(0.0), bi, base0.a, p, n0, v, pixel, light_count, tiled);
        for (int s = 0; s < samples; ++s) imageStore(light_buffer, gid, s, vec4(imageLoad(light_buffer, gid, s).rgb + lit, 1.0));
        return;
    }
    for (int s = 0; s < samples; ++s) {
        if (sample_depth[s] <= 0.0) continue;
        vec4 base_occlusion = texelFetch(g_base_occlusion, gid, s);
        vec4 normal_rm = texelFetch(g_normal_rm, gid, s);
        BrdfInput bi = gbuffer_brdf(base_occlusion, normal_rm, texelFetch(g_f0_f90, gid, s));
        vec3 n = oct_decode(normal_rm.xy);
        vec3 p = world_point(centre_ndc + (u_sample_pos[s] - 0.5) * px_ndc, sample_depth[s]);
        vec3 v = normalize(frame.camera_pos.xyz - p);
        vec3 color;
        if (frame.debug.x == 3) color = rsm_indirect(bi, pixel, p) + shade_gi(bi, p, n, v, base_occlusion.a, 0.0);
        else if (frame.debug.x != 0) color = vec3(frame.debug.x == 1 ? light_visibility(p, n, pixel) : ssao_at(pixel));
        else color = shade_surface(imageLoad(light_buffer, gid, s).rgb, bi, base_occlusion.a, p, n, v, pixel, light_count, tiled);
        imageStore(light_buffer, gid, s, vec4(color, 1.0));
    }
#else
    vec4 base_occlusion = texelFetch(g_base_occlusion, gid, 0);
    vec4 normal_rm = texelFetch(g_normal_rm, gid, 0);
    BrdfInput bi = gbuffer_brdf(base_occlusion, normal_rm, texelFetch(g_f0_f90, gid, 0));
    vec3 n = oct_decode(normal_rm.xy);
    vec2 ndc = (vec2(gid) + 0.5) / vec2(size) * 2.0 - 1.0;
    vec3 p = world_point(ndc, depth);
    vec3 v = normalize(frame.camera_pos.xyz - p);
    vec2 pixel = vec2(gid) + 0.5;
    if (frame.debug.x == 3) {
        imageStore(light_buffer, gid, vec4(rsm_indirect(bi, pixel, p) + shade_gi(bi, p, n, v, base_occlusion.a, 0.0), 1.0));
        return;
    }
    if (frame.debug.x != 0) {
        float value = frame.debug.x == 1 ? light_visibility(p, n, pixel) : ssao_at(pixel);
        imageStore(light_buffer, gid, vec4(vec3(value), 1.0));
        return;
    }
    vec3 color = shade_surface(imageLoad(light_buffer, gid).rgb, bi, base_occlusion.a, p, n, v, pixel, light_count, tiled);
    imageStore(light_buffer, gid, vec4(color, 1.0));
#endif
}
