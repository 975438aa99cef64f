#include "rt/rt_scene.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "core/error.hpp"

namespace candela::rt {

namespace {
template <typename T>
gl::Buffer upload(const std::vector<T>& v) {
    return gl::Buffer(static_cast<GLsizeiptr>(std::max<size_t>(v.size(), 1) * sizeof(T)), v.empty() ? nullptr : v.data());
}

// An RGBA32F buffer texture over `buffer` of `texels` texels (at least one).
gl::Texture texel_view(const gl::Buffer& buffer, std::size_t texels, const char* what) {
    GLint limit = 0;
    glGetIntegerv(GL_MAX_TEXTURE_BUFFER_SIZE, &limit);
    if (texels > static_cast<std::size_t>(limit))
        throw Error(ExitCode::bad_input, std::string("ray tracer: the scene's ") + what + " need " + std::to_string(texels) +
                                             " texels; this GL's GL_MAX_TEXTURE_BUFFER_SIZE is " + std::to_string(limit));
    GLuint id = 0;
    glCreateTextures(GL_TEXTURE_BUFFER, 1, &id);
    glTextureBuffer(id, GL_RGBA32F, buffer.id());
    return gl::Texture::adopt(id, static_cast<int>(std::max<std::size_t>(texels, 1)), 1, GL_RGBA32F);
}
}  // namespace

RtScene::RtScene(const Scene& scene, int default_material) : geometry_(build_rt_geometry(scene, default_material)) {
    TraversalLayout layout;
    try {
        layout = pack_traversal(geometry_);
    } catch (const std::length_error& e) {
        throw Error(ExitCode::bad_input, e.what());
    }
    bvh_nodes_ = upload(layout.nodes);
    bvh_prims_ = upload(layout.prims);
    bvh_nodes_view_ = texel_view(bvh_nodes_, layout.nodes.size(), "BVH nodes");
    bvh_prims_view_ = texel_view(bvh_prims_, layout.prims.size(), "BVH primitives");
    triangles_ = upload(geometry_.triangles);
    triangles_view_ = texel_view(triangles_, geometry_.triangles.size() * (sizeof(TriangleGpu) / 16), "triangles");
    spheres_ = upload(geometry_.spheres);
    emitters_ = upload(geometry_.emitters);
    surfaces_ = upload(geometry_.surfaces);
}

void RtScene::bind() const {
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 6, spheres_.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 7, emitters_.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 11, surfaces_.id());
    glBindTextureUnit(16, bvh_nodes_view_.id());
    glBindTextureUnit(17, bvh_prims_view_.id());
    glBindTextureUnit(18, triangles_view_.id());
}

}  // namespace candela::rt
