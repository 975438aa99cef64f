// RSM's uniform block, shared by rsm.cpp and the GLSL (effects/gpu_block.h).
#include "effects/gpu_block.h"
#define RSM_BINDING 3

GPU_NAMESPACE_BEGIN
GPU_BLOCK(RsmData, RSM_BINDING) {
    int on;         // 1: the gathered indirect irradiance is bound for shading (rsm_indirect runs)
    int downscale;  // 1 full, 2 half, 4 quarter resolution of the gather (rsm.gather)
    int pad0;
    int pad1;
} GPU_BLOCK_INSTANCE(rsm);
GPU_BLOCK_CHECK(RsmData, 16)
GPU_NAMESPACE_END
