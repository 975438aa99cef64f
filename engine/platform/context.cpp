#include "platform/context.hpp"

#include <glad/gl.h>

#include "gl/debug.hpp"

namespace candela {

const char* to_string(Backend backend) {
    switch (backend) {
        case Backend::auto_select: return "auto";
        case Backend::egl: return "egl";
        case Backend::osmesa: return "osmesa";
        case Backend::glfw: return "glfw";
    }
    return "?";
}

std::optional<Backend> parse_backend(const std::string& name) {
    if (name == "auto") return Backend::auto_select;
    if (name == "egl") return Backend::egl;
    if (name == "osmesa") return Backend::osmesa;
    if (name == "glfw") return Backend::glfw;
    return std::nullopt;
}

namespace detail {

std::string load_gl_and_check(const char* backend, GetProcAddress get_proc, std::string& renderer,
                              std::string& version, bool debug) {
    const int loaded = gladLoadGL(reinterpret_cast<GLADloadfunc>(get_proc));
    auto str = [](GLenum name) {
        auto* s = glGetString ? reinterpret_cast<const char*>(glGetString(name)) : nullptr;
        return std::string(s ? s : "unknown");
    };
    renderer = str(GL_RENDERER);
    version = str(GL_VERSION);
    if (loaded == 0 || GLAD_VERSION_MAJOR(loaded) * 10 + GLAD_VERSION_MINOR(loaded) < 45) {
        return std::string(backend) + ": OpenGL 4.5 core is required, got '" + version +
               "' from renderer '" + renderer + "'";
    }
    GLint profile = 0;
    glGetIntegerv(GL_CONTEXT_PROFILE_MASK, &profile);
    if (!(profile & GL_CONTEXT_CORE_PROFILE_BIT)) {
        return std::string(backend) + ": a core profile context is required, got '" + version +
               "' from renderer '" + renderer + "'";
    }
    if (debug) gl::enable_debug_output();
    return {};
}

}  // namespace detail

ContextResult create_context(Backend backend, const ContextOptions& options) {
    ContextResult result;
    std::string error;
    switch (backend) {
        case Backend::egl: result.context = detail::create_egl(options, error); break;
        case Backend::osmesa: result.context = detail::create_osmesa(options, error); break;
        case Backend::glfw: result.context = detail::create_glfw(options, error); break;
        case Backend::auto_select: {
            result.context = detail::create_egl(options, error);
            if (!result.context) {
                std::string osmesa_error;
                result.context = detail::create_osmesa(options, osmesa_error);
                if (!result.context) error += "; " + osmesa_error;
            }
            break;
        }
    }
    if (!result.context) result.error = error;
    return result;
}

}  // namespace candela
