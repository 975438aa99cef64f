// Motion blur's uniform block, shared by engine/effects/motion_blur/motion_blur.cpp and the GLSL
// (gpu/gpu_block.h).
#ifndef CANDELA_MOTION_BLUR_DATA_H
#define CANDELA_MOTION_BLUR_DATA_H
#include "gpu/gpu_block.h"
#define MOTION_BLUR_BINDING 10
#define MOTION_BLUR_IN_UNIT 0        // tilemax.frag's input
// gather.frag's inputs, in this order from MOTION_BLUR_COLOR_UNIT.
#define MOTION_BLUR_COLOR_UNIT 0
#define MOTION_BLUR_VELOCITY_UNIT 1
#define MOTION_BLUR_DEPTH_UNIT 2
#define MOTION_BLUR_NEIGHBOR_UNIT 3

GPU_NAMESPACE_BEGIN
GPU_BLOCK(MotionBlurData, MOTION_BLUR_BINDING) {
    float max_radius;  // largest half-motion in pixels (motion_blur.max_radius); velocities are clamped to it
    float soft_z;      // soft depth extent as a fraction of the view depth (motion_blur.soft_z)
    int samples;       // gather taps (motion_blur.samples)
    int tile;          // pixels per side of a TileMax tile (= max_radius)
} GPU_BLOCK_INSTANCE(motion_blur);
GPU_BLOCK_CHECK(MotionBlurData, 16)
GPU_NAMESPACE_END

#endif
