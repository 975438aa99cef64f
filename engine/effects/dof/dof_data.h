// Depth of field's uniform block, shared by engine/effects/dof/dof.cpp and the GLSL
// (gpu/gpu_block.h).
#ifndef CANDELA_DOF_DATA_H
#define CANDELA_DOF_DATA_H
#include "gpu/gpu_block.h"
#define DOF_BINDING 9
#define DOF_IN_UNIT 0    // a pass's first input (coc: the HDR image; tiles: its input; gather: colour and CoC)
#define DOF_IN2_UNIT 1   // a pass's second input (coc: the depth; gather: the near-field tiles)

GPU_NAMESPACE_BEGIN
GPU_BLOCK(DofData, DOF_BINDING) {
    // Signed CoC radius in pixels of a point at view depth d: coc_scale * (1 - focus / d), with
    // coc_scale = aperture * H / (2 * focus * tan(yfov / 2)) (the radius at infinity); negative
    // in front of the focus plane (the near field). 0: no blur (an orthographic camera).
    float coc_scale;
    float focus;       // focus distance along the view axis, scene units (> 0)
    float max_radius;  // CoC radius clamp in pixels (dof.max_coc / 2)
    int samples;       // gather samples per field (dof.samples)
    int tile;          // pixels per side of a near-field tile
    int tile_reach;    // tiles the near-field dilation reaches: ceil(max_radius / tile)
    int pad0;
    int pad1;
} GPU_BLOCK_INSTANCE(dof);
GPU_BLOCK_CHECK(DofData, 32)
GPU_NAMESPACE_END

#endif
