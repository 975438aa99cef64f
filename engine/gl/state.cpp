#include "gl/state.hpp"

namespace candela::gl {
namespace {
void enable(GLenum cap, bool on) { on ? glEnable(cap) : glDisable(cap); }
}  // namespace

void StateCache::apply(const PipelineState& w) {
    if (changed(k_depth_test_, s_.depth_test, w.depth_test)) enable(GL_DEPTH_TEST, w.depth_test);
    if (changed(k_depth_func_, s_.depth_func, w.depth_func)) glDepthFunc(w.depth_func);
    if (changed(k_depth_write_, s_.depth_write, w.depth_write)) glDepthMask(w.depth_write ? GL_TRUE : GL_FALSE);
    if (changed(k_blend_, s_.blend, w.blend)) enable(GL_BLEND, w.blend);
    const std::array<GLenum, 4> bf = {w.blend_src_rgb, w.blend_dst_rgb, w.blend_src_alpha, w.blend_dst_alpha};
    if (changed(k_blend_func_, blend_func_, bf)) glBlendFuncSeparate(bf[0], bf[1], bf[2], bf[3]);
    set_cull(w.cull, w.cull_face);
    set_front_face(w.front_face);
    if (changed(k_color_write_, s_.color_write, w.color_write)) {
        const GLboolean c = w.color_write ? GL_TRUE : GL_FALSE;
        glColorMask(c, c, c, c);
    }
    if (changed(k_clip_, s_.reversed_z, w.reversed_z))
        glClipControl(GL_LOWER_LEFT, w.reversed_z ? GL_ZERO_TO_ONE : GL_NEGATIVE_ONE_TO_ONE);
    const std::array<float, 2> offset = {w.polygon_offset_factor, w.polygon_offset_units};
    if (changed(k_offset_, offset_, offset)) {
        enable(GL_POLYGON_OFFSET_FILL, offset[0] != 0.0f || offset[1] != 0.0f);
        glPolygonOffset(offset[0], offset[1]);
    }
}

void StateCache::set_cull(bool cull, GLenum face) {
    if (changed(k_cull_, s_.cull, cull)) enable(GL_CULL_FACE, cull);
    if (cull && changed(k_cull_face_, s_.cull_face, face)) glCullFace(face);
}

void StateCache::set_front_face(GLenum face) {
    if (changed(k_front_face_, s_.front_face, face)) glFrontFace(face);
}

void StateCache::bind_framebuffer(GLuint fbo) {
    if (changed(k_fbo_, fbo_, fbo)) glBindFramebuffer(GL_FRAMEBUFFER, fbo);
}

void StateCache::viewport(int x, int y, int w, int h) {
    if (changed(k_viewport_, viewport_, std::array<int, 4>{x, y, w, h})) glViewport(x, y, w, h);
}

void StateCache::use_program(GLuint program) {
    if (changed(k_program_, program_, program)) glUseProgram(program);
}

void StateCache::bind_vertex_array(GLuint vao) {
    if (changed(k_vao_, vao_, vao)) glBindVertexArray(vao);
}

void StateCache::reset() {
    k_depth_test_ = k_depth_func_ = k_depth_write_ = k_blend_ = k_blend_func_ = k_cull_ = k_cull_face_ = k_front_face_ =
        k_color_write_ = k_clip_ = k_offset_ = k_fbo_ = k_viewport_ = k_program_ = k_vao_ = false;
}

std::string StateCache::verify() const {
    auto get_bool = [](GLenum cap) { return glIsEnabled(cap) == GL_TRUE; };
    auto get_int = [](GLenum name) {
        GLint v = 0;
        glGetIntegerv(name, &v);
        return v;
    };
    if (k_depth_test_ && get_bool(GL_DEPTH_TEST) != s_.depth_test) return "GL_DEPTH_TEST";
    if (k_depth_func_ && static_cast<GLenum>(get_int(GL_DEPTH_FUNC)) != s_.depth_func) return "glDepthFunc";
    if (k_depth_write_ && (get_int(GL_DEPTH_WRITEMASK) != 0) != s_.depth_write) return "glDepthMask";
    if (k_blend_ && get_bool(GL_BLEND) != s_.blend) return "GL_BLEND";
    if (k_cull_ && get_bool(GL_CULL_FACE) != s_.cull) return "GL_CULL_FACE";
    if (k_front_face_ && static_cast<GLenum>(get_int(GL_FRONT_FACE)) != s_.front_face) return "glFrontFace";
    if (k_clip_ && (static_cast<GLenum>(get_int(GL_CLIP_DEPTH_MODE)) == GL_ZERO_TO_ONE) != s_.reversed_z) return "glClipControl";
    if (k_offset_ && get_bool(GL_POLYGON_OFFSET_FILL) != (offset_[0] != 0.0f || offset_[1] != 0.0f))
        return "GL_POLYGON_OFFSET_FILL";
    if (k_program_ && static_cast<GLuint>(get_int(GL_CURRENT_PROGRAM)) != program_) return "glUseProgram";
    if (k_fbo_ && static_cast<GLuint>(get_int(GL_DRAW_FRAMEBUFFER_BINDING)) != fbo_) return "glBindFramebuffer";
    return {};
}

}  // namespace candela::gl
