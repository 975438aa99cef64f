// RSM's uniform block, shared by rsm.cpp and the GLSL (gpu/gpu_block.h).
#ifndef CANDELA_RSM_DATA_H
#define CANDELA_RSM_DATA_H
#include "gpu/gpu_block.h"
#define RSM_BINDING 3
#define RSM_INDIRECT_UNIT 10    // the gathered indirect light, while shading (camera views)
#define RSM_VIEWS_BINDING 4     // SSBO: RsmView per layer (gather.frag)
// gather.frag's inputs: the camera's depth and normals, the RSM arrays (position, normal, flux).
#define RSM_DEPTH_UNIT 0
#define RSM_NORMALS_UNIT 1
#define RSM_POSITION_UNIT 2
#define RSM_NORMAL_UNIT 3
#define RSM_FLUX_UNIT 4

GPU_NAMESPACE_BEGIN
GPU_BLOCK(RsmData, RSM_BINDING) {
    int on;         // 1: the gathered indirect irradiance is bound for shading (rsm_indirect runs)
    int downscale;  // 1 full, 2 half, 4 quarter resolution of the gather (rsm.gather)
    int pad0;
    int pad1;
} GPU_BLOCK_INSTANCE(rsm);
GPU_BLOCK_CHECK(RsmData, 16)

// One RSM layer's view, the element of the RSM_VIEWS_BINDING buffer (gather.frag).
GPU_STRUCT(RsmView) {
    mat4 view_proj;
    float light;             // the light's index
    float first_layer;       // the first layer of its RSM light
    float layer_count;       // that light's layer count
    float face_half_width;   // cube faces: the face's tangent half-width (> 1: a guard band beyond
                             // the 90 degrees); 0: one view (directional, spot)
};
GPU_STRUCT_CHECK(RsmView, 80)
GPU_NAMESPACE_END

#endif
