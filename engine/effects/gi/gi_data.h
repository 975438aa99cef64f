// The GI probes' uniform block, shared by gi.cpp and the GLSL (effects/gpu_block.h): the probe
// grid, the atlases' layout and the current update iteration.
#include "effects/gpu_block.h"
#define GI_BINDING 6
#define GI_IRRADIANCE_UNIT 21  // RGBA32F atlas: rgb irradiance E (W/m^2 per unit radiance), a probe active
#define GI_DEPTH_UNIT 22       // RG32F atlas: mean distance and mean squared distance
#define GI_RAYS_BINDING 13     // SSBO: per probe and ray, rgb radiance and the hit distance, then the direction
#define GI_RAYS_UNIT 23        // the same buffer as a buffer texture (probe_update.comp reads it)

GPU_NAMESPACE_BEGIN
GPU_BLOCK(GiData, GI_BINDING) {
    vec4 origin;     // xyz: the first probe's position; w: 1 when the probes are bound for shading
    vec4 spacing;    // xyz: distance between probes per axis; w: the shading bias (world units)
    ivec4 counts;    // xyz: probes per axis; w: irradiance texels per tile side (interior)
    ivec4 params;    // x: depth texels per tile side (interior); y: rays per probe; z: iteration; w: first probe of this batch
    vec4 fparams;    // x: weight of this iteration's estimate; y: the distance a miss records; z: seed; w: depth sharpness
    mat4 rotation;   // this iteration's random rotation of the ray directions
} GPU_BLOCK_INSTANCE(gi);
GPU_BLOCK_CHECK(GiData, 144)
GPU_NAMESPACE_END
