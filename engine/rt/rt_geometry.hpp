#pragma once
// The Scene as the ray tracer sees it, on the CPU: world-space triangles (nodes marked
// extras.sphere are replaced by their exact sphere), analytic spheres, emissive triangles with a
// power CDF, and a BVH over all of them. Layouts mirror shaders/rt/scene.glsl. No GL here: the
// tests, benchmarks and the fuzz target build it without a context (rt_scene.hpp uploads it).
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "gpu/rt_scene.h"
#include "rt/bvh.hpp"
#include "scene/scene.hpp"

namespace candela::rt {

struct TriangleGpu {
    glm::vec4 p0, p1, p2;  // p0.w material (int bits), p1.w node (int bits), p2.w 1: single-sided opaque
    glm::vec4 n0, n1, n2;  // n0.w: probability that emitter sampling picks this triangle
    glm::vec4 uv_a;        // uv0 of p0, uv0 of p1
    glm::vec4 uv_b;        // uv0 of p2, uv1 of p0
    glm::vec4 uv_c;        // uv1 of p1, uv1 of p2
    glm::vec4 t0, t1, t2;  // world tangents, w = handedness (normal maps)
};
using SphereGpu = gpu::RtSphere;  // gpu/rt_scene.h
using EmitterGpu = gpu::Emitter;
static_assert(sizeof(TriangleGpu) == 192 && sizeof(SphereGpu) == 32 && sizeof(EmitterGpu) == 16);

// CPU-side geometry (also what the C++ tests and benchmarks use).
struct RtGeometry {
    std::vector<TriangleGpu> triangles;
    // COLOR_0 of each triangle's corners (3 per triangle, in corner order), only when some
    // vertex colour differs from white (has_vertex_colors); empty otherwise.
    std::vector<glm::vec4> colors;
    std::vector<SphereGpu> spheres;
    std::vector<EmitterGpu> emitters;
    // Every triangle by area (EmitterGpu layout: pdf = area / total): uniform points over all
    // surfaces, for the indirect mode without occlusion between bounce points.
    std::vector<EmitterGpu> surfaces;
    double emitted_power = 0.0;  // sum of luminance(emission) * area over emitters
    bool has_transmission = false;
    bool has_blend = false;  // alphaMode BLEND materials: composited along camera rays
    bool has_mask = false;   // alphaMode MASK materials: every ray tests the cutoff at candidate hits
    bool has_vertex_colors = false;  // `colors` is filled (HAS_VERTEX_COLORS in the shaders)
    Bvh bvh;
};

// `default_material`: the material index used for primitives without one (GpuScene appends the
// default material after the scene's).
RtGeometry build_rt_geometry(const Scene& scene, int default_material, const BvhOptions& options = {});

// build_rt_geometry into `geometry`, reusing its vectors' storage (a posed scene, built again).
void rebuild_rt_geometry(RtGeometry& geometry, const Scene& scene, int default_material, const BvhOptions& options = {});

// The scene's (posed) geometry again with `geometry`'s BVH topology, its boxes refit bottom-up
// (refit_bvh): for posed scenes (animation), whose triangles move but keep their count and order.
// Returns the refit's ms (the BVH part; the triangles are rebuilt in full), or -1 with `geometry`
// unchanged when the triangle or sphere count differs (build again then).
double refit_rt_geometry(RtGeometry& geometry, const Scene& scene, int default_material, const BvhOptions& options = {});

// The boxes the BVH is built over: the triangles', then the spheres', in primitive id order.
std::vector<Aabb> primitive_boxes(const RtGeometry& geometry);

// The BVH as the GPU traverses it: two RGBA32F buffer textures (shaders/rt/scene.glsl, trace()).
// On llvmpipe a texel fetch gathers a vector of lanes at once where an SSBO load with a per-lane
// address becomes a loop over the lanes, and a visit here reads 4 texels where the 32-byte node
// layout read 6 (the node, then both children's boxes).
// - nodes: 4 texels per interior node of the Bvh, holding both children:
//   (left bmin, left ref) (left bmax, 0) (right bmin, right ref) (right bmax, 0), refs as int bits.
//   A ref >= 0 is the index of an interior node here; a ref < 0 is a leaf,
//   -1 - (first * 64 + count - 1): `count` (1..64) primitive records from record `first`.
//   Node 0 is the root. A root that is a leaf (or the empty BVH) becomes node 0 with the root as
//   its left child and, on the right, an empty box (+inf, -inf: missed by every ray) with the ref
//   kTraversalNoChild (so is the empty BVH's left child).
// - prims: 3 texels per primitive in leaf order, so that a leaf's primitives are contiguous:
//   triangle (p0, id) (p1, 0) (p2, 0); sphere (center, id) (radius, 0, 0, 0) (0); id (int bits) is
//   the index in triangles, or triangles.size() + the sphere's index.
struct TraversalLayout {
    std::vector<glm::vec4> nodes;
    std::vector<glm::vec4> prims;
};
inline constexpr std::int32_t kTraversalNoChild = std::numeric_limits<std::int32_t>::min();
inline constexpr std::size_t kTraversalMaxPrimitives = std::size_t{1} << 25;  // leaf refs hold first * 64
// Throws std::length_error past kTraversalMaxPrimitives primitives.
TraversalLayout pack_traversal(const RtGeometry& geometry);
// The same into `out`, reusing its storage (posed geometry, packed again per time slice).
void pack_traversal(const RtGeometry& geometry, TraversalLayout& out);
// What the GPU traversal relies on, checked by walking `layout` from the root: refs in range, every
// primitive record reached exactly once with its id and positions, each primitive inside the box
// its leaf was reached through, children inside their parent's box. Empty if it holds, else the
// first violation. For the tests and the fuzz target.
std::string traversal_layout_violation(const RtGeometry& geometry, const TraversalLayout& layout);

}  // namespace candela::rt
