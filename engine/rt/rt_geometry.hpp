#pragma once
// The Scene as the ray tracer sees it, on the CPU: world-space triangles (nodes marked
// extras.sphere are replaced by their exact sphere), analytic spheres, emissive triangles with a
// power CDF, and a BVH over all of them. Layouts mirror shaders/rt/scene.glsl. No GL here: the
// tests, benchmarks and the fuzz target build it without a context (rt_scene.hpp uploads it).
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "rt/bvh.hpp"
#include "scene/scene.hpp"

namespace candela::rt {

struct TriangleGpu {
    glm::vec4 p0, p1, p2;  // p0.w material (int bits), p1.w node (int bits)
    glm::vec4 n0, n1, n2;  // n0.w: probability that emitter sampling picks this triangle
    glm::vec4 uv_a;        // uv0 of p0, uv0 of p1
    glm::vec4 uv_b;        // uv0 of p2, uv1 of p0
    glm::vec4 uv_c;        // uv1 of p1, uv1 of p2
    glm::vec4 t0, t1, t2;  // world tangents, w = handedness (normal maps)
};
struct SphereGpu {
    glm::vec4 center_radius;
    glm::ivec4 material_node;  // x material, y node, z emitter-selection pdf (float bits) if emissive
};
struct EmitterGpu {
    std::uint32_t triangle;  // a triangle index, or triangles.size() + a sphere index
    float cdf, pdf, area;
};
static_assert(sizeof(TriangleGpu) == 192 && sizeof(SphereGpu) == 32 && sizeof(EmitterGpu) == 16);

// CPU-side geometry (also what the C++ tests and benchmarks use).
struct RtGeometry {
    std::vector<TriangleGpu> triangles;
    std::vector<SphereGpu> spheres;
    std::vector<EmitterGpu> emitters;
    // Every triangle by area (EmitterGpu layout: pdf = area / total): uniform points over all
    // surfaces, for the indirect mode without occlusion between bounce points.
    std::vector<EmitterGpu> surfaces;
    double emitted_power = 0.0;  // sum of luminance(emission) * area over emitters
    bool has_transmission = false;
    bool has_blend = false;  // alphaMode BLEND materials: composited along camera rays
    Bvh bvh;
};

// `default_material`: the material index used for primitives without one (GpuScene appends the
// default material after the scene's).
RtGeometry build_rt_geometry(const Scene& scene, int default_material, const BvhOptions& options = {});

}  // namespace candela::rt
