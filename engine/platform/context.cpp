#include "platform/context.hpp"

#include <glad/gl.h>

#include <algorithm>
#include <vector>

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

namespace {

// The OpenGL features Candela uses, by the extension that introduced each and the core version
// that absorbed it. A driver below 4.5 is named with the ones it lacks, so that a user can see
// whether a newer driver or a different backend would help.
struct GlRequirement {
    const char* extension;
    int core_version;  // major * 10 + minor
    const char* use;
};
constexpr GlRequirement kRequirements[] = {
    {"GL_ARB_clip_control", 45, "reversed-Z depth"},
    {"GL_ARB_direct_state_access", 45, "object creation and updates"},
    {"GL_ARB_texture_barrier", 45, "reading a target while drawing the next layer"},
    {"GL_ARB_buffer_storage", 44, "immutable buffers"},
    {"GL_ARB_compute_shader", 43, "the ray tracer and the compute passes"},
    {"GL_ARB_shader_storage_buffer_object", 43, "scene, light and BVH buffers"},
    {"GL_KHR_debug", 43, "GL error reporting"},
    {"GL_ARB_texture_view", 43, "the ray tracer's sRGB view of the scene textures"},
    {"GL_ARB_shader_image_load_store", 42, "ray-tracer output images"},
    {"GL_ARB_texture_storage", 42, "immutable textures"},
    {"GL_ARB_texture_cube_map_array", 40, "reflection probes"},
    {"GL_ARB_timer_query", 33, "pass timings"},
};

}  // namespace

std::string missing_gl_features(int version, const std::vector<std::string>& extensions) {
    std::string missing;
    for (const GlRequirement& r : kRequirements) {
        if (version >= r.core_version) continue;
        if (std::find(extensions.begin(), extensions.end(), r.extension) != extensions.end()) continue;
        if (!missing.empty()) missing += ", ";
        missing += std::string(r.extension) + " (" + r.use + ")";
    }
    return missing;
}

std::string describe_shortfall(const char* backend, GetProcAddress get_proc) {
    const int loaded = gladLoadGL(reinterpret_cast<GLADloadfunc>(get_proc));
    if (loaded == 0 || !glGetString) return std::string(backend) + ": the driver's OpenGL entry points could not be loaded";
    auto str = [](GLenum name) {
        auto* s = reinterpret_cast<const char*>(glGetString(name));
        return std::string(s ? s : "unknown");
    };
    const int version = GLAD_VERSION_MAJOR(loaded) * 10 + GLAD_VERSION_MINOR(loaded);
    std::vector<std::string> extensions;
    if (glGetStringi) {
        GLint count = 0;
        glGetIntegerv(GL_NUM_EXTENSIONS, &count);
        for (GLint i = 0; i < count; ++i) {
            auto* e = reinterpret_cast<const char*>(glGetStringi(GL_EXTENSIONS, static_cast<GLuint>(i)));
            if (e) extensions.emplace_back(e);
        }
    }
    std::string text = std::string(backend) + ": OpenGL 4.5 core is required; the driver offers '" +
                       str(GL_VERSION) + "' on '" + str(GL_RENDERER) + "'";
    const std::string missing = missing_gl_features(version, extensions);
    if (!missing.empty()) text += "; missing: " + missing;
    return text;
}

std::string load_gl_and_check(const char* backend, GetProcAddress get_proc, std::string& renderer,
                              std::string& version, bool debug) {
    const int loaded = gladLoadGL(reinterpret_cast<GLADloadfunc>(get_proc));
    auto str = [](GLenum name) {
        auto* s = glGetString ? reinterpret_cast<const char*>(glGetString(name)) : nullptr;
        return std::string(s ? s : "unknown");
    };
    renderer = str(GL_RENDERER);
    version = str(GL_VERSION);
    if (loaded == 0 || GLAD_VERSION_MAJOR(loaded) * 10 + GLAD_VERSION_MINOR(loaded) < 45)
        return describe_shortfall(backend, get_proc);
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
                else result.notice = "EGL is unavailable (" + error + "); falling back to OSMesa";
            }
            break;
        }
    }
    if (!result.context) result.error = error;
    return result;
}

}  // namespace candela
