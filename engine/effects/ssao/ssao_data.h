// SSAO's uniform block, shared by engine/effects/ssao/ssao.cpp and the GLSL (effects/gpu_block.h).
#include "effects/gpu_block.h"
#define SSAO_BINDING 2

GPU_NAMESPACE_BEGIN
GPU_BLOCK(SsaoData, SSAO_BINDING) {
    float radius;  // world units (ao.radius)
    float bias;    // start offset and depth tolerance, fraction of the radius (ssao.bias)
    int samples;   // directions per pixel (ssao.samples)
    int steps;     // steps marched along each direction (ssao.steps)
    int on;        // 1: the AO buffer is bound for shading (the ssao pass runs this frame)
    int blur;      // blur radius in AO pixels (ssao.blur)
    int downscale; // 1 full resolution, 2 half (ssao.resolution)
    int pad;
} GPU_BLOCK_INSTANCE(ssao);
GPU_BLOCK_CHECK(SsaoData, 32)
GPU_NAMESPACE_END
