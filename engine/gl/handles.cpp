#include "gl/handles.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"

namespace candela::gl {

Buffer::Buffer(GLsizeiptr size, const void* data, GLbitfield flags) : size_(size) {
    GLuint id = 0;
    glCreateBuffers(1, &id);
    glNamedBufferStorage(id, size > 0 ? size : 1, size > 0 ? data : nullptr, flags);
    static_cast<Handle&>(*this) = Handle(id);
}

void Buffer::update(GLintptr offset, GLsizeiptr size, const void* data) {
    glNamedBufferSubData(id(), offset, size, data);
}

int full_mip_levels(int width, int height) {
    return 1 + static_cast<int>(std::floor(std::log2(static_cast<double>(std::max({width, height, 1})))));
}

Texture Texture::create_2d(GLenum internal_format, int width, int height, int levels) {
    if (levels <= 0) levels = full_mip_levels(width, height);
    GLuint id = 0;
    glCreateTextures(GL_TEXTURE_2D, 1, &id);
    glTextureStorage2D(id, levels, internal_format, width, height);
    Texture texture(id);
    texture.width_ = width;
    texture.height_ = height;
    texture.format_ = internal_format;
    return texture;
}

Texture Texture::create_2d_multisample(GLenum internal_format, int width, int height, int samples) {
    GLuint id = 0;
    glCreateTextures(GL_TEXTURE_2D_MULTISAMPLE, 1, &id);
    glTextureStorage2DMultisample(id, samples, internal_format, width, height, GL_TRUE);
    Texture texture(id);
    texture.width_ = width;
    texture.height_ = height;
    texture.format_ = internal_format;
    texture.samples_ = samples;
    return texture;
}

Sampler Sampler::create(GLenum min_filter, GLenum mag_filter, GLenum wrap_s, GLenum wrap_t) {
    GLuint id = 0;
    glCreateSamplers(1, &id);
    glSamplerParameteri(id, GL_TEXTURE_MIN_FILTER, static_cast<GLint>(min_filter));
    glSamplerParameteri(id, GL_TEXTURE_MAG_FILTER, static_cast<GLint>(mag_filter));
    glSamplerParameteri(id, GL_TEXTURE_WRAP_S, static_cast<GLint>(wrap_s));
    glSamplerParameteri(id, GL_TEXTURE_WRAP_T, static_cast<GLint>(wrap_t));
    return Sampler(id);
}

Framebuffer Framebuffer::create() {
    GLuint id = 0;
    glCreateFramebuffers(1, &id);
    return Framebuffer(id);
}

void Framebuffer::attach(GLenum attachment, const Texture& texture, int level) {
    glNamedFramebufferTexture(id(), attachment, texture.id(), level);
}

void Framebuffer::check_complete(const char* what) const {
    const GLenum status = glCheckNamedFramebufferStatus(id(), GL_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE) {
        char buf[160];
        std::snprintf(buf, sizeof buf, "framebuffer '%s' is incomplete (status 0x%04x)", what, status);
        throw Error(ExitCode::internal, buf);
    }
}

VertexArray VertexArray::create() {
    GLuint id = 0;
    glCreateVertexArrays(1, &id);
    return VertexArray(id);
}

Query Query::create(GLenum target) {
    GLuint id = 0;
    glCreateQueries(target, 1, &id);
    return Query(id);
}

}  // namespace candela::gl
