// The GI probes' uniform block, shared by gi.cpp and the GLSL (gpu/gpu_block.h): the probe
// grid, the atlases' layout and the current update iteration.
#ifndef CANDELA_GI_DATA_H
#define CANDELA_GI_DATA_H
#include "gpu/gpu_block.h"
#define GI_BINDING 6
#define GI_IRRADIANCE_UNIT 21  // RGBA32F atlas: rgb irradiance E (W/m^2 per unit radiance), a probe active
#define GI_DEPTH_UNIT 22       // RG32F atlas: mean distance and mean squared distance
#define GI_RAYS_BINDING 13     // SSBO: per probe and ray, rgb radiance and the hit distance, then the direction
#define GI_RAYS_UNIT 23        // the same buffer as a buffer texture (probe_update.comp reads it)
#define GI_OFFSETS_UNIT 27     // RGBA32F, one texel per probe (its tile): xyz the probe's offset from its grid point
#define GI_IRRADIANCE_IMAGE 0  // probe_update.comp writes the atlases through these image units
#define GI_DEPTH_IMAGE 1
#define GI_OFFSETS_IMAGE 2     // probe_relocate.comp writes the offsets

GPU_NAMESPACE_BEGIN
GPU_BLOCK(GiData, GI_BINDING) {
    vec3 origin;             // the first probe's position
    float on;                // 1 when the probes are bound for shading; -1 in relocation's trace
    vec3 spacing;            // distance between probes per axis
    float shading_bias;      // world units
    ivec3 probe_counts;      // probes per axis
    int irradiance_texels;   // irradiance texels per tile side (interior)
    int depth_texels;        // depth texels per tile side (interior)
    int rays_per_probe;
    int iteration;
    int first_probe;         // the first probe of this batch
    float weight;            // weight of this iteration's estimate (1: replace)
    float miss_distance;     // the distance a miss records
    float seed;              // the random streams' seed (uint bits)
    float depth_sharpness;
    mat4 rotation;           // this iteration's random rotation of the ray directions
} GPU_BLOCK_INSTANCE(gi);
GPU_BLOCK_CHECK(GiData, 144)
GPU_NAMESPACE_END

#endif
