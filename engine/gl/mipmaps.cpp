#include "gl/mipmaps.hpp"

#include <algorithm>

#include "gpu/bindings.h"

namespace candela::gl {

void draw_mipmaps(GLuint program, GLuint texture, GLenum format, int width, int height, int levels) {
    if (levels < 2) return;
    GLint old_program = 0, old_vao = 0, old_fbo = 0, old_texture = 0, old_sampler = 0, old_unit = 0, viewport[4] = {0, 0, 0, 0};
    glGetIntegerv(GL_CURRENT_PROGRAM, &old_program);
    glGetIntegerv(GL_VERTEX_ARRAY_BINDING, &old_vao);
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &old_fbo);
    glGetIntegerv(GL_VIEWPORT, viewport);
    glGetIntegerv(GL_ACTIVE_TEXTURE, &old_unit);
    glActiveTexture(GL_TEXTURE0 + SOURCE_UNIT);
    glGetIntegerv(GL_TEXTURE_BINDING_2D, &old_texture);
    glGetIntegerv(GL_SAMPLER_BINDING, &old_sampler);
    glActiveTexture(static_cast<GLenum>(old_unit));
    const GLboolean was_srgb = glIsEnabled(GL_FRAMEBUFFER_SRGB);
    // On, a draw into an sRGB level encodes (the per-fragment sRGB conversion), as a blit into it
    // does; the sRGB view decodes what it samples.
    const bool srgb = format == GL_SRGB8_ALPHA8;
    if (srgb != (was_srgb == GL_TRUE)) srgb ? glEnable(GL_FRAMEBUFFER_SRGB) : glDisable(GL_FRAMEBUFFER_SRGB);

    // Vertex arrays and framebuffers are per context: made and deleted here, so that any context
    // sharing the texture and the program can call this.
    GLuint vao = 0, fbo = 0;
    glCreateVertexArrays(1, &vao);
    glCreateFramebuffers(1, &fbo);
    glUseProgram(program);
    glBindVertexArray(vao);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, fbo);
    glBindSampler(SOURCE_UNIT, 0);
    int w = width, h = height;
    for (int level = 1; level < levels; ++level) {
        const int nw = std::max(w / 2, 1), nh = std::max(h / 2, 1);
        GLuint view = 0;
        glGenTextures(1, &view);  // a view needs a name that has never been bound
        glTextureView(view, GL_TEXTURE_2D, texture, format, static_cast<GLuint>(level - 1), 1, 0, 1);
        glTextureParameteri(view, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
        glTextureParameteri(view, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        glTextureParameteri(view, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        glTextureParameteri(view, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
        glBindTextureUnit(SOURCE_UNIT, view);
        glNamedFramebufferTexture(fbo, GL_COLOR_ATTACHMENT0, texture, level);
        glNamedFramebufferDrawBuffer(fbo, GL_COLOR_ATTACHMENT0);
        glViewport(0, 0, nw, nh);
        glDrawArrays(GL_TRIANGLE_FAN, 0, 4);
        glBindTextureUnit(SOURCE_UNIT, 0);
        glDeleteTextures(1, &view);  // the draw keeps what it reads alive until it has run
        w = nw;
        h = nh;
    }
    glDeleteFramebuffers(1, &fbo);
    glDeleteVertexArrays(1, &vao);
    glBindTextureUnit(SOURCE_UNIT, static_cast<GLuint>(old_texture));
    glBindSampler(SOURCE_UNIT, static_cast<GLuint>(old_sampler));
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, static_cast<GLuint>(old_fbo));
    glBindVertexArray(static_cast<GLuint>(old_vao));
    glUseProgram(static_cast<GLuint>(old_program));
    glViewport(viewport[0], viewport[1], viewport[2], viewport[3]);
    if (srgb != (was_srgb == GL_TRUE)) was_srgb ? glEnable(GL_FRAMEBUFFER_SRGB) : glDisable(GL_FRAMEBUFFER_SRGB);
}

}  // namespace candela::gl
