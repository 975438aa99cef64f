#version 450 core
// Tiled deferred lighting (Andersson 2011, "DirectX 11 Rendering in Battlefield 3"): one 16x16
// workgroup per screen tile finds the tile's depth range, culls the light list against the tile's
// sub-frustum (range-limited point and spot lights; unbounded lights always pass), then shades
// its pixels from the G-buffer with only the lights that survived. Adds to the light buffer,
// which already holds the emission.
#include "../common/scene_data.glsl"
#include "../lighting/gbuffer.glsl"
#include "../lighting/shading.glsl"

layout(local_size_x = 16, local_size_y = 16) in;

layout(binding = 0) uniform sampler2D g_base_occlusion;
layout(binding = 1) uniform sampler2D g_normal_rm;
layout(binding = 2) uniform sampler2D g_f0_f90;
layout(binding = 3) uniform sampler2D g_depth;
layout(rgba32f, binding = 0) uniform image2D light_buffer;

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

void main() {
    ivec2 size = imageSize(light_buffer);
    ivec2 gid = ivec2(gl_GlobalInvocationID.xy);
    uint local = gl_LocalInvocationIndex;
    bool inside = all(lessThan(gid, size));
    float depth = inside ? texelFetch(g_depth, gid, 0).r : 0.0;
    bool geometry = inside && depth > 0.0;  // reversed-Z: cleared to 0 where nothing was drawn

    if (local == 0u) {
        s_depth_min = 0x7f7fffffu;
        s_depth_max = 0u;
    }
    if (local < uint(kMaxTiledLights / 32)) s_mask[local] = 0u;
    barrier();
    // Positive floats order like their bit patterns.
    if (geometry) {
        atomicMin(s_depth_min, floatBitsToUint(depth));
        atomicMax(s_depth_max, floatBitsToUint(depth));
    }
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

    vec4 base_occlusion = texelFetch(g_base_occlusion, gid, 0);
    vec4 normal_rm = texelFetch(g_normal_rm, gid, 0);
    BrdfInput bi = gbuffer_brdf(base_occlusion, normal_rm, texelFetch(g_f0_f90, gid, 0));
    vec3 n = oct_decode(normal_rm.xy);
    vec2 ndc = (vec2(gid) + 0.5) / vec2(size) * 2.0 - 1.0;
    vec4 pw = frame.inv_view_proj * vec4(ndc, depth, 1.0);
    vec3 p = pw.xyz / pw.w;
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
    vec3 color = imageLoad(light_buffer, gid).rgb;
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
    color += shade_ambient(bi, p, n, v, base_occlusion.a * ssao_at(pixel));
    color += rsm_indirect(bi, pixel, p);
    color += shade_gi(bi, p, n, v, base_occlusion.a, 0.0);
    imageStore(light_buffer, gid, vec4(color, 1.0));
}
