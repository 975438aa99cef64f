#version 450 core
// The forward pass's light culling (the light_tiles pass, render/passes/forward_opaque.cpp): one
// workgroup per 16x16 screen tile finds the lights that can reach the tile's sub-frustum (point
// and spot lights by their range or cutoff, common/lights.glsl light_reach; the others always
// pass) and writes them as a bit set, which forward/forward.frag (TILED_LIGHTS) walks in index
// order. A culled light adds exactly nothing to the tile's pixels (the range window and the cutoff
// are 0 beyond the reach), so the image is the one without culling. The test is that of the
// deferred lighting (deferred/light.comp) without the tile's depth range: the forward pass has
// not drawn yet.
#include "../common/scene_data.glsl"
#include "../lighting/tile_frustum.glsl"

layout(local_size_x = 64) in;
layout(std430, binding = LIGHT_TILES_BINDING) writeonly buffer LightTiles { uint tile_masks[]; };

const int kMaxWords = 64;  // 2048 lights (render/passes/forward_opaque.cpp: kMaxTiledForwardLights)
shared uint s_mask[kMaxWords];
shared vec4 s_planes[4];

void main() {
    uint local = gl_LocalInvocationIndex;
    ivec2 size = ivec2(frame.viewport.xy);
    ivec2 tiles = (size + 15) / 16;
    int words = (frame.light_count + 31) / 32;
    if (local < uint(kMaxWords)) s_mask[local] = 0u;
    if (local == 0u) {
        // Between the near plane (reversed-Z 1) and a depth beyond it (0.5): the side planes of a
        // tile are the same at any depth, for a perspective or an orthographic projection.
        vec2 lo = vec2(gl_WorkGroupID.xy * 16u) / vec2(size) * 2.0 - 1.0;
        vec2 hi = vec2(min((gl_WorkGroupID.xy + 1u) * 16u, uvec2(size))) / vec2(size) * 2.0 - 1.0;
        vec4 planes[4];
        vec2 zrange;
        tile_frustum(inverse(frame.proj), lo, hi, 1.0, 0.5, planes, zrange);
        for (int i = 0; i < 4; ++i) s_planes[i] = planes[i];
    }
    barrier();
    for (int i = int(local); i < min(frame.light_count, 32 * kMaxWords); i += 64)
        if (light_meets_planes(lights[i], s_planes)) atomicOr(s_mask[i >> 5], 1u << uint(i & 31));
    barrier();
    uint tile = gl_WorkGroupID.y * uint(tiles.x) + gl_WorkGroupID.x;
    for (int w = int(local); w < words; w += 64) tile_masks[tile * uint(words) + uint(w)] = s_mask[w];
}
