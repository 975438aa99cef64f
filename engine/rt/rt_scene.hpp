#pragma once
// The ray tracer's geometry (rt_geometry.hpp) uploaded to SSBOs.
#include "gl/handles.hpp"
#include "rt/rt_geometry.hpp"

namespace candela::rt {

class RtScene {
public:
    RtScene(const Scene& scene, int default_material);
    const RtGeometry& geometry() const { return geometry_; }
    void bind() const;  // SSBO bindings 3..7 and 11

private:
    RtGeometry geometry_;
    gl::Buffer nodes_, prim_indices_, triangles_, spheres_, emitters_, surfaces_;
};

}  // namespace candela::rt
