// The shadows effect's uniform block, shared by shadows.cpp and the GLSL (gpu/gpu_block.h).
#ifndef CANDELA_SHADOWS_DATA_H
#define CANDELA_SHADOWS_DATA_H
#include "gpu/gpu_block.h"
#define SHADOWS_BINDING 1
#define SHADOW_VIEWS_BINDING 3  // SSBO: ShadowView per shadow view (layer)
#define SHADOW_UNIT 7           // the depth array with a GEQUAL compare sampler (PCF)
#define SHADOW_DEPTH_UNIT 8     // the same array with a raw sampler (blocker search)

GPU_NAMESPACE_BEGIN
GPU_BLOCK(ShadowsData, SHADOWS_BINDING) {
    int filter_mode;     // 0 off (no shadow pass this frame), 1 hard, 2 pcf, 3 pcss (shadows.filter)
    int pcf_size;        // PCF kernel width in taps (shadows.pcf_size)
    int blocker_taps;    // PCSS blocker-search taps (shadows.pcss_blocker_taps)
    int pcss_taps;       // PCSS filter taps (shadows.pcss_taps)
    float normal_bias;   // receiver offset along its normal, texels (shadows.normal_bias)
    float depth_bias;    // reference moved towards the light, texels (shadows.depth_bias)
    float resolution;    // texels per side of a layer of the shadow atlas (shadows.resolution)
    float max_radius;    // largest PCSS search/filter radius, texels (shadows.max_radius)
    float receiver_slope_bias;  // multiple of tan(theta) per texel of filter taps (shadows.receiver_slope_bias)
    float pad0;
    float pad1;
    float pad2;
} GPU_BLOCK_INSTANCE(shadows);
GPU_BLOCK_CHECK(ShadowsData, 48)

// One shadow view (a layer of the depth array), the element of the SHADOW_VIEWS_BINDING buffer.
GPU_STRUCT(ShadowView) {
    mat4 view_proj;
    float kind;          // 0 orthographic, 1 perspective
    float texel_size;    // orthographic: world units; perspective: tangent units (times the distance)
    float depth_range;   // orthographic: the depth range; perspective: the near plane
    float layer;         // the array layer of its tile
    float cascade_end;   // orthographic cascades: the view depth where this cascade ends
    float light_size;    // world units; directional: angular diameter in radians
    float tile_u;        // the tile's corner in the layer (texture coordinates)
    float tile_v;
    float tile_scale;    // the tile's side over the layer's (1, 1/2, 1/4, ...)
    float tile_texels;   // the tile's side in texels: the view's resolution
    float pad0;
    float pad1;
};
GPU_STRUCT_CHECK(ShadowView, 112)
GPU_NAMESPACE_END

#endif
