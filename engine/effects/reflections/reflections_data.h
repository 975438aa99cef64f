// The reflections effect's uniform block, shared by reflections.cpp and the GLSL
// (gpu/gpu_block.h).
#include "gpu/gpu_block.h"
#define REFLECTIONS_BINDING 4
#define REFLECTIONS_PROBES_UNIT 14    // the probes' filtered cube array
#define REFLECTIONS_PROBES_BINDING 5  // SSBO: ProbeData per probe

GPU_NAMESPACE_BEGIN
GPU_BLOCK(ReflectionsData, REFLECTIONS_BINDING) {
    int probes;      // reflection probes bound (0: none, and inside a probe's own faces)
    int levels;      // mip levels of their prefiltered cubes
    int refraction;  // 1: transmissive surfaces refract (the effect is planned)
    int pad;
} GPU_BLOCK_INSTANCE(reflections);
GPU_BLOCK_CHECK(ReflectionsData, 16)
GPU_NAMESPACE_END
