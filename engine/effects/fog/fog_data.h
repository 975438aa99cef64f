// The fog effect's uniform block, shared by fog.cpp and fog.frag (effects/gpu_block.h).
#include "effects/gpu_block.h"
#define FOG_BINDING 5

GPU_NAMESPACE_BEGIN
GPU_BLOCK(FogData, FOG_BINDING) {
    vec4 colour_density;  // rgb: in-scattered radiance of the fog, a: extinction per world unit (fog.density)
} GPU_BLOCK_INSTANCE(fog);
GPU_BLOCK_CHECK(FogData, 16)
GPU_NAMESPACE_END
