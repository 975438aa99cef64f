// The ray tracer's storage-buffer records, declared once for C++ (engine/rt/rt_geometry.cpp builds
// them) and GLSL (shaders/rt/scene.glsl reads them), through gpu/gpu_block.h. The triangles are
// not here: they are a buffer texture of 12 RGBA32F texels each (texel fetches, which llvmpipe
// gathers for 8 lanes at once), laid out by rt::TriangleGpu and read by load_triangle().
#ifndef CANDELA_GPU_RT_SCENE_H
#define CANDELA_GPU_RT_SCENE_H

#include "gpu/bindings.h"
#include "gpu/gpu_block.h"

GPU_NAMESPACE_BEGIN

// An analytic sphere (a node marked extras.sphere), the element of RT_SPHERES_BINDING.
GPU_STRUCT(RtSphere) {
    vec3 center;
    float radius;
    int material;
    int node;
    float emitter_pdf;  // emissive: the probability that emitter sampling picks it; else 0
    int pad0;
};
GPU_STRUCT_CHECK(RtSphere, 32)

// An emissive triangle or sphere and the cumulative distribution used to pick one by power, the
// element of RT_EMITTERS_BINDING (and of RT_SURFACES_BINDING: every triangle by area).
GPU_STRUCT(Emitter) {
    uint triangle;  // a triangle index, or the triangle count + a sphere index
    float cdf;      // inclusive
    float pdf;      // the probability of choosing this emitter
    float area;
};
GPU_STRUCT_CHECK(Emitter, 16)

GPU_NAMESPACE_END

#endif
