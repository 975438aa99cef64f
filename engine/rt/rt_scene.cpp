#include "rt/rt_scene.hpp"

#include <algorithm>
#include <chrono>
#include <stdexcept>
#include <string>

#include "core/error.hpp"
#include "gpu/bindings.h"

namespace candela::rt {

namespace {
double ms_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

// Uploads `v` into `buffer`: in place when the size is unchanged (posed geometry), else into new
// storage (at least one element). Returns whether the storage is new (views must be remade).
template <typename T>
bool upload(gl::Buffer& buffer, const std::vector<T>& v) {
    const auto bytes = static_cast<GLsizeiptr>(std::max<size_t>(v.size(), 1) * sizeof(T));
    if (buffer && buffer.size() == bytes) {
        if (!v.empty()) buffer.update(0, bytes, v.data());
        return false;
    }
    buffer = gl::Buffer(bytes, v.empty() ? nullptr : v.data(), GL_DYNAMIC_STORAGE_BIT);
    return true;
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

RtScene::RtScene(const Scene& scene, int default_material)
    : default_material_(default_material), geometry_(build_rt_geometry(scene, default_material)) {
    RtUpdateStats unused;
    TraversalLayout layout;
    upload_all(unused, layout);
}

void RtScene::upload_all(RtUpdateStats& stats, TraversalLayout& layout) {
    auto t0 = std::chrono::steady_clock::now();
    try {
        pack_traversal(geometry_, layout);
    } catch (const std::length_error& e) {
        throw Error(ExitCode::bad_input, e.what());
    }
    stats.pack_ms = ms_since(t0);
    t0 = std::chrono::steady_clock::now();
    if (upload(bvh_nodes_, layout.nodes)) bvh_nodes_view_ = texel_view(bvh_nodes_, layout.nodes.size(), "BVH nodes");
    if (upload(bvh_prims_, layout.prims)) bvh_prims_view_ = texel_view(bvh_prims_, layout.prims.size(), "BVH primitives");
    if (upload(triangles_, geometry_.triangles))
        triangles_view_ = texel_view(triangles_, geometry_.triangles.size() * (sizeof(TriangleGpu) / 16), "triangles");
    if (geometry_.has_vertex_colors && upload(colors_, geometry_.colors))
        colors_view_ = texel_view(colors_, geometry_.colors.size(), "vertex colours");
    upload(spheres_, geometry_.spheres);
    upload(emitters_, geometry_.emitters);
    upload(surfaces_, geometry_.surfaces);
    stats.upload_ms = ms_since(t0);
}

RtUpdateStats RtScene::update(const Scene& scene, RtUpdate how) {
    RtUpdateStats stats;
    auto t0 = std::chrono::steady_clock::now();
    if (how == RtUpdate::refit) {
        const double refit_ms = refit_rt_geometry(geometry_, scene, default_material_);
        stats.refit = refit_ms >= 0.0;
        if (stats.refit) {
            stats.bvh_ms = refit_ms;
            stats.geometry_ms = ms_since(t0) - refit_ms;
        }
    }
    if (!stats.refit) {
        t0 = std::chrono::steady_clock::now();
        rebuild_rt_geometry(geometry_, scene, default_material_);
        stats.bvh_ms = geometry_.bvh.stats.build_ms;
        stats.geometry_ms = ms_since(t0) - stats.bvh_ms;
    }
    upload_all(stats, layout_);
    const auto t1 = std::chrono::steady_clock::now();
    glFinish();  // the upload is done when the GL has the data
    stats.upload_ms += ms_since(t1);
    return stats;
}

void RtScene::bind() const {
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, RT_SPHERES_BINDING, spheres_.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, RT_EMITTERS_BINDING, emitters_.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, RT_SURFACES_BINDING, surfaces_.id());
    glBindTextureUnit(RT_BVH_NODES_UNIT, bvh_nodes_view_.id());
    glBindTextureUnit(RT_BVH_PRIMS_UNIT, bvh_prims_view_.id());
    glBindTextureUnit(RT_TRIANGLES_UNIT, triangles_view_.id());
    if (geometry_.has_vertex_colors) glBindTextureUnit(RT_COLORS_UNIT, colors_view_.id());
}

}  // namespace candela::rt
