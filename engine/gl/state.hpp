#pragma once
// The GL state of a pass, set through one small cache that skips redundant calls and counts the
// real ones (sokol/Filament style). Each pass applies a complete PipelineState, so nothing one
// pass sets can leak into the next; reset() forgets the cache after foreign code (ImGui).
#include <glad/gl.h>

#include <array>
#include <string>

namespace candela::gl {

struct PipelineState {
    bool depth_test = false;
    GLenum depth_func = GL_GREATER;  // reversed-Z
    bool depth_write = true;
    bool blend = false;
    GLenum blend_src_rgb = GL_ONE, blend_dst_rgb = GL_ZERO, blend_src_alpha = GL_ONE, blend_dst_alpha = GL_ZERO;
    bool cull = false;
    GLenum cull_face = GL_BACK;
    GLenum front_face = GL_CCW;
    bool color_write = true;
    bool reversed_z = true;  // glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE)
    // glPolygonOffset(factor, units) with GL_POLYGON_OFFSET_FILL when either is non-zero
    // (shadow casters: negative values push depth away from the light under reversed-Z).
    float polygon_offset_factor = 0.0f;
    float polygon_offset_units = 0.0f;
};

class StateCache {
public:
    // Applies every field of `state` (changed ones only).
    void apply(const PipelineState& state);
    // Per-draw changes within a pass.
    void set_cull(bool cull, GLenum face);
    void set_front_face(GLenum face);
    void bind_framebuffer(GLuint fbo);
    void viewport(int x, int y, int w, int h);
    void use_program(GLuint program);
    void bind_vertex_array(GLuint vao);

    // Forget everything: the next apply() sets every field.
    void reset();
    // Queries GL and compares with what the cache believes; returns "" or a description of the
    // first mismatch (a GL call that bypassed the cache). Debug use: it stalls.
    std::string verify() const;

    int real_calls() const { return real_calls_; }
    int skipped_calls() const { return skipped_calls_; }

private:
    template <typename T>
    bool changed(bool& known, T& cached, const T& wanted) {
        if (known && cached == wanted) {
            ++skipped_calls_;
            return false;
        }
        known = true;
        cached = wanted;
        ++real_calls_;
        return true;
    }
    PipelineState s_{};
    // Whether each field's cached value is known to match GL.
    bool k_depth_test_ = false, k_depth_func_ = false, k_depth_write_ = false, k_blend_ = false, k_blend_func_ = false,
         k_cull_ = false, k_cull_face_ = false, k_front_face_ = false, k_color_write_ = false, k_clip_ = false, k_offset_ = false,
         k_fbo_ = false, k_viewport_ = false, k_program_ = false, k_vao_ = false;
    std::array<GLenum, 4> blend_func_{};
    std::array<float, 2> offset_{};
    GLuint fbo_ = 0, program_ = 0, vao_ = 0;
    std::array<int, 4> viewport_{};
    int real_calls_ = 0, skipped_calls_ = 0;
};

}  // namespace candela::gl
