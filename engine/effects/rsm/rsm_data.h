// RSM's uniform block, shared by rsm.cpp and the GLSL (gpu/gpu_block.h).
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
GPU_NAMESPACE_END
