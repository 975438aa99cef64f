// The reflections effect's uniform block, shared by reflections.cpp and the GLSL
// (gpu/gpu_block.h).
#ifndef CANDELA_REFLECTIONS_DATA_H
#define CANDELA_REFLECTIONS_DATA_H
#include "gpu/gpu_block.h"
#define REFLECTIONS_BINDING 4
#define REFLECTIONS_PROBES_UNIT 14    // the probes' filtered cube array
#define REFLECTIONS_PROBES_BINDING 5  // SSBO: ProbeData per probe
#define REFLECTIONS_DISTANCE_UNIT 28  // R32F cube array: distance from each probe to what it saw
#define REFLECTIONS_FACE_DEPTH_UNIT 0 // probe_distance.comp: the captured face's depth
#define REFLECTIONS_DISTANCE_IMAGE 0  // probe_distance.comp writes the distance cube array here
#define REFLECTIONS_FAR 1.0e30        // the distance of a texel that saw no geometry (the sky)

GPU_NAMESPACE_BEGIN
GPU_BLOCK(ReflectionsData, REFLECTIONS_BINDING) {
    int probes;      // reflection probes bound (0: none, and inside a probe's own faces)
    int levels;      // mip levels of their prefiltered cubes
    int refraction;  // 1: transmissive surfaces refract (the effect is planned)
    int capture;     // 1 inside a probe's capture: the forward pass writes in alpha the luminance
                     // of the emission that the area lights also add (see reflections_reflection_radiance)
    int parallax;    // 1: lookups of probes without a box march their distance cube
    int pad0;
    int pad1;
    int pad2;
} GPU_BLOCK_INSTANCE(reflections);
GPU_BLOCK_CHECK(ReflectionsData, 32)

// One reflection probe, the element of the REFLECTIONS_PROBES_BINDING buffer.
GPU_STRUCT(ProbeData) {
    vec3 position;          // the capture point
    float radius;           // influence radius when there is no box
    vec3 box_min;           // box-projected lookups inside [box_min, box_max] when has_box = 1
    float has_box;
    vec3 box_max;
    float reflective_only;  // >= 0: lights only reflective surfaces (metallic with roughness below
                            // it, or transmissive); < 0: every surface in range
};
GPU_STRUCT_CHECK(ProbeData, 48)
GPU_NAMESPACE_END

#endif
