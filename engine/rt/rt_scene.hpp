#pragma once
// The ray tracer's geometry (rt_geometry.hpp) uploaded: the BVH in its traversal layout and the
// triangles as buffer textures (texel fetches are what llvmpipe reads fastest), the rest as SSBOs.
#include "gl/handles.hpp"
#include "rt/rt_geometry.hpp"

namespace candela::rt {

class RtScene {
public:
    RtScene(const Scene& scene, int default_material);
    const RtGeometry& geometry() const { return geometry_; }
    void bind() const;  // SSBO bindings 6, 7 and 11; texture units 16 (BVH nodes), 17 (BVH primitives), 18 (triangles)

private:
    RtGeometry geometry_;
    gl::Buffer bvh_nodes_, bvh_prims_, triangles_, spheres_, emitters_, surfaces_;
    gl::Texture bvh_nodes_view_, bvh_prims_view_, triangles_view_;
};

}  // namespace candela::rt
