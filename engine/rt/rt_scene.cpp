#include "rt/rt_scene.hpp"

#include <algorithm>

namespace candela::rt {

namespace {
template <typename T>
gl::Buffer upload(const std::vector<T>& v) {
    return gl::Buffer(static_cast<GLsizeiptr>(std::max<size_t>(v.size(), 1) * sizeof(T)), v.empty() ? nullptr : v.data());
}
}  // namespace

RtScene::RtScene(const Scene& scene, int default_material) : geometry_(build_rt_geometry(scene, default_material)) {
    nodes_ = upload(geometry_.bvh.nodes);
    prim_indices_ = upload(geometry_.bvh.prim_indices);
    triangles_ = upload(geometry_.triangles);
    spheres_ = upload(geometry_.spheres);
    emitters_ = upload(geometry_.emitters);
    surfaces_ = upload(geometry_.surfaces);
}

void RtScene::bind() const {
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, nodes_.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, prim_indices_.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 5, triangles_.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 6, spheres_.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 7, emitters_.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 11, surfaces_.id());
}

}  // namespace candela::rt
