#version 450 core
// The forward pass's light culling (the light_tiles pass, render/passes/forward_opaque.cpp): one
// workgroup per 16x16 screen tile finds the lights whose range can reach the tile's sub-frustum
// (range-limited point and spot lights; lights without a range always pass) and writes them as a
// bit set, which forward/forward.frag (TILED_LIGHTS) walks in index order. A culled light adds
// exactly nothing to the tile's pixels (the range window is 0 beyond the range), so the image is
// the one without culling. The test is that of the deferred lighting (deferred/light.comp) without
// the tile's depth range: the forward pass has not drawn yet.
#include "../common/scene_data.glsl"

layout(local_size_x = 64) in;
layout(std430, binding = LIGHT_TILES_BINDING) writeonly buffer LightTiles { uint tile_masks[]; };

const int kMaxWords = 64;  // 2048 lights (render/passes/forward_opaque.cpp: kMaxTiledForwardLights)
shared uint s_mask[kMaxWords];
shared vec4 s_planes[4];

vec3 view_point(mat4 inv_proj, vec2 ndc, float depth) {
    vec4 p = inv_proj * vec4(ndc, depth, 1.0);
    return p.xyz / p.w;
}

bool light_in_tile(LightData light) {
    int type = int(light.type);
    float range = light.range;
    if ((type != LIGHT_POINT && type != LIGHT_SPOT) || range <= 0.0) return true;
    vec3 c = (frame.view * vec4(light.position, 1.0)).xyz;
    for (int i = 0; i < 4; ++i)
        if (dot(s_planes[i].xyz, c) + s_planes[i].w < -range) return false;
    return true;
}

void main() {
    uint local = gl_LocalInvocationIndex;
    ivec2 size = ivec2(frame.viewport.xy);
    ivec2 tiles = (size + 15) / 16;
    int words = (frame.light_count + 31) / 32;
    if (local < uint(kMaxWords)) s_mask[local] = 0u;
    if (local == 0u) {
        // Side planes through a tile edge at two depths (reversed-Z: 1 the near plane, 0.5 beyond
        // it): for a perspective or an orthographic projection alike, the plane of the edge.
        mat4 inv_proj = inverse(frame.proj);
        vec2 lo = vec2(gl_WorkGroupID.xy * 16u) / vec2(size) * 2.0 - 1.0;
        vec2 hi = vec2(min((gl_WorkGroupID.xy + 1u) * 16u, uvec2(size))) / vec2(size) * 2.0 - 1.0;
        vec3 n00 = view_point(inv_proj, lo, 1.0), n10 = view_point(inv_proj, vec2(hi.x, lo.y), 1.0);
        vec3 n01 = view_point(inv_proj, vec2(lo.x, hi.y), 1.0), n11 = view_point(inv_proj, hi, 1.0);
        vec3 f00 = view_point(inv_proj, lo, 0.5), f10 = view_point(inv_proj, vec2(hi.x, lo.y), 0.5);
        vec3 f01 = view_point(inv_proj, vec2(lo.x, hi.y), 0.5), f11 = view_point(inv_proj, hi, 0.5);
        vec3 centre = (n00 + n10 + n01 + n11 + f00 + f10 + f01 + f11) * 0.125;
        vec3 a[4] = vec3[4](n00, n10, n11, n01);
        vec3 b[4] = vec3[4](n01, n00, n10, n11);
        vec3 f[4] = vec3[4](f00, f10, f11, f01);
        for (int i = 0; i < 4; ++i) {
            vec3 nrm = normalize(cross(b[i] - a[i], f[i] - a[i]));
            if (dot(nrm, centre - a[i]) < 0.0) nrm = -nrm;
            s_planes[i] = vec4(nrm, -dot(nrm, a[i]));
        }
    }
    barrier();
    for (int i = int(local); i < min(frame.light_count, 32 * kMaxWords); i += 64)
        if (light_in_tile(lights[i])) atomicOr(s_mask[i >> 5], 1u << uint(i & 31));
    barrier();
    uint tile = gl_WorkGroupID.y * uint(tiles.x) + gl_WorkGroupID.x;
    for (int w = int(local); w < words; w += 64) tile_masks[tile * uint(words) + uint(w)] = s_mask[w];
}
