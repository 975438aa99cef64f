#pragma once
// The forward path: opaque and masked geometry, the environment behind it, then alpha-blended
// geometry back to front; linear HDR (RGBA32F) out. The frame-graph issue splits this into passes.
#include "gl/handles.hpp"
#include "image/image.hpp"
#include "render/gpu_scene.hpp"
#include "shader/shader_library.hpp"

namespace candela {

struct FrameStats {
    int draw_calls = 0;
    std::size_t triangles = 0;
};

class ForwardRenderer {
public:
    // Builds the programs; throws candela::Error (internal) if a shader does not compile.
    ForwardRenderer(const ShaderLibrary& shaders, GpuScene& scene);

    // Renders one frame into the internal target (resized as needed).
    void render(const Camera& camera, int width, int height);
    // Reads the last frame back: linear radiance, top row first.
    ImageF read_radiance() const;
    const FrameStats& stats() const { return stats_; }

private:
    void resize(int width, int height);
    void draw(const GpuScene::Draw& d, GLenum cull_face, bool cull);

    GpuScene& scene_;
    gl::Program forward_, sky_;
    gl::Texture color_, depth_;
    gl::Framebuffer fbo_;
    gl::Buffer frame_ubo_;
    gl::VertexArray empty_vao_;
    int width_ = 0, height_ = 0;
    FrameStats stats_;
};

}  // namespace candela
