#include "render/forward_renderer.hpp"

#include <algorithm>

#include <glm/gtc/type_ptr.hpp>

namespace candela {

ForwardRenderer::ForwardRenderer(const ShaderLibrary& shaders, GpuScene& scene) : scene_(scene) {
    forward_ = shaders.build_or_throw({"forward", {{ShaderStage::vertex, "forward/forward.vert"},
                                                   {ShaderStage::fragment, "forward/forward.frag"}}, {}});
    sky_ = shaders.build_or_throw({"sky", {{ShaderStage::vertex, "forward/sky.vert"},
                                           {ShaderStage::fragment, "forward/sky.frag"}}, {}});
    frame_ubo_ = gl::Buffer(sizeof(FrameData), nullptr, GL_DYNAMIC_STORAGE_BIT);
    empty_vao_ = gl::VertexArray::create();
}

void ForwardRenderer::resize(int width, int height) {
    if (width == width_ && height == height_) return;
    width_ = width;
    height_ = height;
    color_ = gl::Texture::create_2d(GL_RGBA32F, width, height, 1);
    depth_ = gl::Texture::create_2d(GL_DEPTH_COMPONENT32F, width, height, 1);
    fbo_ = gl::Framebuffer::create();
    fbo_.attach(GL_COLOR_ATTACHMENT0, color_);
    fbo_.attach(GL_DEPTH_ATTACHMENT, depth_);
    fbo_.check_complete("forward");
}

void ForwardRenderer::draw(const GpuScene::Draw& d, GLenum cull_face, bool cull) {
    if (cull) {
        glEnable(GL_CULL_FACE);
        glCullFace(cull_face);
    } else {
        glDisable(GL_CULL_FACE);
    }
    // A mirroring transform reverses the winding of its triangles.
    glFrontFace(d.mirrored ? GL_CW : GL_CCW);
    glProgramUniformMatrix4fv(forward_.id(), 0, 1, GL_FALSE, glm::value_ptr(d.model));
    glProgramUniformMatrix3fv(forward_.id(), 1, 1, GL_FALSE, glm::value_ptr(d.normal_matrix));
    glProgramUniform1i(forward_.id(), 2, d.primitive_material);
    for (int s = 0; s < 5; ++s) {
        const auto su = static_cast<size_t>(s);
        const gl::Texture& t = d.textures[su] >= 0 ? scene_.texture(d.textures[su], d.srgb[su]) : scene_.white_texture();
        glBindTextureUnit(static_cast<GLuint>(s), t.id());
        glBindSampler(static_cast<GLuint>(s), scene_.sampler(d.samplers[su]).id());
    }
    glDrawElementsBaseVertex(GL_TRIANGLES, d.index_count, GL_UNSIGNED_INT,
                             reinterpret_cast<const void*>(d.first_index * sizeof(std::uint32_t)), d.base_vertex);
    ++stats_.draw_calls;
    stats_.triangles += static_cast<std::size_t>(d.index_count / 3);
}

void ForwardRenderer::render(const Camera& camera, int width, int height) {
    resize(width, height);
    stats_ = {};
    const float aspect = static_cast<float>(width) / static_cast<float>(height);
    FrameData frame{};
    frame.view = glm::inverse(camera.world);
    frame.proj = projection_matrix(camera, aspect);
    frame.view_proj = frame.proj * frame.view;
    frame.inv_view_proj = glm::inverse(frame.view_proj);
    frame.camera_pos = glm::vec4(glm::vec3(camera.world[3]), 1.0f);
    frame.env_radiance = glm::vec4(scene_.environment_radiance(), scene_.has_environment_map() ? 1.0f : 0.0f);
    for (int i = 0; i < 9; ++i) frame.env_sh[i] = glm::vec4(scene_.environment_sh()[static_cast<size_t>(i)], 0.0f);
    frame.counts = glm::ivec4(scene_.light_count(), scene_.environment_mips(), 0, 0);
    frame_ubo_.update(0, sizeof(FrameData), &frame);

    // State is set explicitly: nothing is assumed from a previous frame or pass.
    glBindFramebuffer(GL_FRAMEBUFFER, fbo_.id());
    glViewport(0, 0, width, height);
    glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);  // reversed-Z: near = 1, far = 0
    glDisable(GL_SCISSOR_TEST);
    glDisable(GL_BLEND);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_GREATER);
    glDepthMask(GL_TRUE);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    const float clear_color[4] = {0, 0, 0, 1};
    const float clear_depth = 0.0f;
    glClearNamedFramebufferfv(fbo_.id(), GL_COLOR, 0, clear_color);
    glClearNamedFramebufferfv(fbo_.id(), GL_DEPTH, 0, &clear_depth);

    glBindBufferBase(GL_UNIFORM_BUFFER, 0, frame_ubo_.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, scene_.materials().id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, scene_.lights().id());
    glBindTextureUnit(5, scene_.environment_map().id());
    glBindSampler(5, 0);

    // Opaque and masked.
    glUseProgram(forward_.id());
    glBindVertexArray(scene_.vertex_array().id());
    std::vector<const GpuScene::Draw*> blended;
    for (const auto& d : scene_.draws()) {
        if (d.alpha_mode == AlphaMode::blend) {
            blended.push_back(&d);
            continue;
        }
        draw(d, GL_BACK, !d.double_sided);
    }

    // Environment where nothing was drawn (depth still at the cleared far value 0).
    glUseProgram(sky_.id());
    glBindVertexArray(empty_vao_.id());
    glDisable(GL_CULL_FACE);
    glDepthFunc(GL_GEQUAL);
    glDepthMask(GL_FALSE);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    ++stats_.draw_calls;

    // Blended: back to front by the view depth of each draw's bounds centre; depth test on,
    // depth write off; double-sided meshes draw back faces first.
    if (!blended.empty()) {
        auto view_depth = [&](const GpuScene::Draw* d) {
            return (frame.view * glm::vec4(d->world_bounds.center(), 1.0f)).z;  // more negative = farther
        };
        std::stable_sort(blended.begin(), blended.end(), [&](auto* a, auto* b) { return view_depth(a) < view_depth(b); });
        glUseProgram(forward_.id());
        glBindVertexArray(scene_.vertex_array().id());
        glDepthFunc(GL_GREATER);
        glEnable(GL_BLEND);
        glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ZERO, GL_ONE);
        for (const auto* d : blended) {
            if (d->double_sided) draw(*d, GL_FRONT, true);
            draw(*d, GL_BACK, true);
        }
        glDisable(GL_BLEND);
    }
    // Leave the defaults that other code expects.
    glDepthMask(GL_TRUE);
    glDepthFunc(GL_LESS);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    glFrontFace(GL_CCW);
    glClipControl(GL_LOWER_LEFT, GL_NEGATIVE_ONE_TO_ONE);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

ImageF ForwardRenderer::read_radiance() const {
    ImageF img(width_, height_, 4);
    glGetTextureImage(color_.id(), 0, GL_RGBA, GL_FLOAT, static_cast<GLsizei>(img.pixels.size() * sizeof(float)),
                      img.pixels.data());
    // GL's first row is the bottom one.
    const size_t row = static_cast<size_t>(width_) * 4;
    for (int y = 0; y < height_ / 2; ++y)
        std::swap_ranges(img.pixels.begin() + static_cast<std::ptrdiff_t>(static_cast<size_t>(y) * row),
                         img.pixels.begin() + static_cast<std::ptrdiff_t>(static_cast<size_t>(y + 1) * row),
                         img.pixels.begin() + static_cast<std::ptrdiff_t>(static_cast<size_t>(height_ - 1 - y) * row));
    return img;
}

}  // namespace candela
