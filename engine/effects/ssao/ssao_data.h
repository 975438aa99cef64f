// SSAO's uniform block, shared by engine/effects/ssao/ssao.cpp and the GLSL (gpu/gpu_block.h).
#ifndef CANDELA_SSAO_DATA_H
#define CANDELA_SSAO_DATA_H
#include "gpu/gpu_block.h"
#define SSAO_BINDING 2
#define SSAO_UNIT 9           // the blurred AO, while shading (camera views)
// ssao.frag's inputs: the camera's depth and normals, the 4x4 noise; blur.frag's: the raw AO.
#define SSAO_DEPTH_UNIT 0
#define SSAO_NORMALS_UNIT 1
#define SSAO_NOISE_UNIT 2
#define SSAO_BLUR_IN_UNIT 0

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

#endif
