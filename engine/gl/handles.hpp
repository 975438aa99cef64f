#pragma once
// Move-only owners of GL objects, created with DSA (glCreate*). Engine APIs pass these, never raw
// names; .id() is for the GL calls inside engine/gl and the passes.
#include <glad/gl.h>

#include <string>
#include <utility>

namespace candela::gl {

template <void (*Destroy)(GLuint)>
class Handle {
public:
    Handle() = default;
    explicit Handle(GLuint id) : id_(id) {
        if (id_) ++live_;
    }
    ~Handle() { reset(); }
    Handle(Handle&& other) noexcept : id_(std::exchange(other.id_, 0)) {}
    Handle& operator=(Handle&& other) noexcept {
        if (this != &other) {
            reset();
            id_ = std::exchange(other.id_, 0);
        }
        return *this;
    }
    Handle(const Handle&) = delete;
    Handle& operator=(const Handle&) = delete;

    GLuint id() const { return id_; }
    explicit operator bool() const { return id_ != 0; }
    void reset() {
        if (id_) {
            Destroy(id_);
            --live_;
        }
        id_ = 0;
    }
    // Objects of this kind alive now (leak checks in tests).
    static int live() { return live_; }

private:
    GLuint id_ = 0;
    static inline int live_ = 0;
};

namespace detail {
inline void delete_buffer(GLuint id) { glDeleteBuffers(1, &id); }
inline void delete_texture(GLuint id) { glDeleteTextures(1, &id); }
inline void delete_framebuffer(GLuint id) { glDeleteFramebuffers(1, &id); }
inline void delete_vertex_array(GLuint id) { glDeleteVertexArrays(1, &id); }
inline void delete_program(GLuint id) { glDeleteProgram(id); }
inline void delete_shader(GLuint id) { glDeleteShader(id); }
inline void delete_query(GLuint id) { glDeleteQueries(1, &id); }
inline void delete_sampler(GLuint id) { glDeleteSamplers(1, &id); }
}  // namespace detail

class Buffer : public Handle<detail::delete_buffer> {
public:
    Buffer() = default;
    // Immutable storage (glNamedBufferStorage); flags e.g. GL_DYNAMIC_STORAGE_BIT.
    Buffer(GLsizeiptr size, const void* data, GLbitfield flags = 0);
    void update(GLintptr offset, GLsizeiptr size, const void* data);
    GLsizeiptr size() const { return size_; }

private:
    GLsizeiptr size_ = 0;
};

// Levels of a full mip chain down to 1x1: 1 + floor(log2(max(width, height))).
int full_mip_levels(int width, int height);

class Texture : public Handle<detail::delete_texture> {
public:
    Texture() = default;
    // A 2D texture with `levels` mip levels (0: a full chain).
    // `levels` <= 0: the full chain, full_mip_levels(width, height).
    static Texture create_2d(GLenum internal_format, int width, int height, int levels = 1);
    // A multisampled 2D texture (GL_TEXTURE_2D_MULTISAMPLE, fixed sample locations), `samples` > 1.
    static Texture create_2d_multisample(GLenum internal_format, int width, int height, int samples);
    // Takes ownership of a texture made elsewhere (e.g. an array texture).
    static Texture adopt(GLuint id, int width, int height, GLenum internal_format) {
        Texture t(id);
        t.width_ = width;
        t.height_ = height;
        t.format_ = internal_format;
        return t;
    }
    int width() const { return width_; }
    int height() const { return height_; }
    GLenum format() const { return format_; }
    int samples() const { return samples_; }  // 1: not multisampled

private:
    using Handle::Handle;
    int width_ = 0, height_ = 0;
    GLenum format_ = 0;
    int samples_ = 1;
};

// Binds `texture_id` (0: none) to texture unit `unit` with no sampler object, so that it is read
// with the texture's own filtering and wrapping.
inline void bind_texture_unit(GLuint unit, GLuint texture_id) {
    glBindTextureUnit(unit, texture_id);
    glBindSampler(unit, 0);
}
inline void bind_texture_unit(GLuint unit, const Texture& texture) { bind_texture_unit(unit, texture.id()); }

class Sampler : public Handle<detail::delete_sampler> {
public:
    Sampler() = default;
    static Sampler create(GLenum min_filter, GLenum mag_filter, GLenum wrap_s, GLenum wrap_t);

private:
    using Handle::Handle;
};

class Framebuffer : public Handle<detail::delete_framebuffer> {
public:
    static Framebuffer create();
    void attach(GLenum attachment, const Texture& texture, int level = 0);
    // Throws candela::Error (internal) naming `what` when incomplete.
    void check_complete(const char* what) const;

private:
    using Handle::Handle;
};

class VertexArray : public Handle<detail::delete_vertex_array> {
public:
    static VertexArray create();

private:
    using Handle::Handle;
};

class Query : public Handle<detail::delete_query> {
public:
    static Query create(GLenum target);

private:
    using Handle::Handle;
};

class Shader : public Handle<detail::delete_shader> {
public:
    using Handle::Handle;
};

class Program : public Handle<detail::delete_program> {
public:
    Program() = default;
    using Handle::Handle;
};

}  // namespace candela::gl
