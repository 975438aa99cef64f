#pragma once
// The ray tracer's geometry (rt_geometry.hpp) uploaded: the BVH in its traversal layout and the
// triangles as buffer textures (texel fetches are what llvmpipe reads fastest), the rest as SSBOs.
#include "gl/handles.hpp"
#include "rt/rt_geometry.hpp"

namespace candela::rt {

// How RtScene::update replaces the geometry of a posed scene (animation):
// - rebuild: a new binned-SAH BVH over the posed triangles;
// - refit: the current BVH's topology with its boxes recomputed bottom-up (refit_bvh), cheaper
//   to build and as fast to trace while the triangles stay near where the tree was built (the
//   motion within a shutter); falls back to a rebuild when the primitive count changed.
enum class RtUpdate { rebuild, refit };

// What one update cost, wall times in ms.
struct RtUpdateStats {
    bool refit = false;       // false: rebuilt (asked for, or the refit fell back)
    double geometry_ms = 0.0;  // world-space triangles, emitters and surfaces from the scene
    double bvh_ms = 0.0;       // the BVH build or refit
    double pack_ms = 0.0;      // the traversal layout
    double upload_ms = 0.0;    // buffer uploads, until the GL has them (glFinish)
    double total_ms() const { return geometry_ms + bvh_ms + pack_ms + upload_ms; }
};

class RtScene {
public:
    RtScene(const Scene& scene, int default_material);
    const RtGeometry& geometry() const { return geometry_; }
    void bind() const;  // SSBO bindings 6, 7 and 11; texture units 16 (BVH nodes), 17 (BVH primitives), 18 (triangles)
    // Replaces the geometry with the scene's as it is now (posed: same materials and nodes, moved
    // triangles) and uploads it; buffers of unchanged size are updated in place.
    RtUpdateStats update(const Scene& scene, RtUpdate how);

private:
    // Packs geometry_ into `layout` and uploads it all (pack_ms, upload_ms).
    void upload_all(RtUpdateStats& stats, TraversalLayout& layout);
    TraversalLayout layout_;  // kept after the first update: its storage is reused by the next
    int default_material_ = -1;
    RtGeometry geometry_;
    gl::Buffer bvh_nodes_, bvh_prims_, triangles_, colors_, spheres_, emitters_, surfaces_;
    gl::Texture bvh_nodes_view_, bvh_prims_view_, triangles_view_, colors_view_;
};

}  // namespace candela::rt
