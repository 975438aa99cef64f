// EGL without a window: the device platform when a hardware driver offers a DRM device,
// otherwise Mesa's surfaceless platform. Rendering goes to FBOs, so no surface is needed.
#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <cstring>
#include <vector>

#include "platform/context.hpp"

namespace candela::detail {
namespace {

std::string egl_error_name(EGLint code) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "EGL error 0x%04x", static_cast<unsigned>(code));
    return buf;
}

bool has_extension(const char* list, const char* name) {
    if (!list) return false;
    const size_t n = std::strlen(name);
    for (const char* p = list; (p = std::strstr(p, name)); p += n)
        if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return true;
    return false;
}

class EglShared final : public SharedContext {
public:
    EglShared(EGLDisplay display, EGLContext context) : display_(display), context_(context) {}
    ~EglShared() override { eglDestroyContext(display_, context_); }
    bool make_current() override { return eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_) == EGL_TRUE; }
    void release() override {
        eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        eglReleaseThread();
    }

private:
    EGLDisplay display_;
    EGLContext context_;
};

class EglContext final : public Context {
public:
    EglContext(EGLDisplay display, EGLContext context, bool debug, const char* platform)
        : display_(display), context_(context), debug_(debug), platform_(platform) {}
    ~EglContext() override {
        eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        eglDestroyContext(display_, context_);
        eglTerminate(display_);
        eglReleaseThread();
    }
    Backend backend() const override { return Backend::egl; }
    bool make_current() override {
        if (!eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_)) return false;
        std::string r, v;
        return load_gl_and_check("egl", reinterpret_cast<GetProcAddress>(eglGetProcAddress), r, v,
                                 false)
            .empty();
    }
    std::unique_ptr<SharedContext> create_shared() override {
        const EGLint attribs[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 5,
                                  EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
        EGLContext shared = eglCreateContext(display_, EGL_NO_CONFIG_KHR, context_, attribs);
        if (shared == EGL_NO_CONTEXT) return nullptr;
        return std::make_unique<EglShared>(display_, shared);
    }
    std::string init() {
        if (!eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_))
            return std::string("egl: eglMakeCurrent failed (") + egl_error_name(eglGetError()) + ")";
        return load_gl_and_check("egl", reinterpret_cast<GetProcAddress>(eglGetProcAddress),
                                 renderer_, version_, debug_);
    }

private:
    EGLDisplay display_;
    EGLContext context_;
    bool debug_;
    const char* platform_;
};

EGLDisplay open_display(const char*& platform_name) {
    const char* client_ext = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    auto get_platform_display = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
        eglGetProcAddress("eglGetPlatformDisplayEXT"));
    if (!get_platform_display) return EGL_NO_DISPLAY;
    // A GPU: a device that names a DRM node.
    if (has_extension(client_ext, "EGL_EXT_platform_device")) {
        auto query_devices =
            reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
        auto query_device_string = reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(
            eglGetProcAddress("eglQueryDeviceStringEXT"));
        EGLint count = 0;
        if (query_devices && query_device_string && query_devices(0, nullptr, &count) && count > 0) {
            std::vector<EGLDeviceEXT> devices(static_cast<size_t>(count));
            query_devices(count, devices.data(), &count);
            for (EGLDeviceEXT device : devices) {
                const char* dev_ext = query_device_string(device, EGL_EXTENSIONS);
                if (!has_extension(dev_ext, "EGL_EXT_device_drm")) continue;
                EGLDisplay d = get_platform_display(EGL_PLATFORM_DEVICE_EXT, device, nullptr);
                if (d != EGL_NO_DISPLAY) {
                    platform_name = "device";
                    return d;
                }
            }
        }
    }
    if (has_extension(client_ext, "EGL_MESA_platform_surfaceless")) {
        platform_name = "surfaceless";
        return get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    }
    return EGL_NO_DISPLAY;
}

}  // namespace

std::unique_ptr<Context> create_egl(const ContextOptions& options, std::string& error) {
    const char* platform = "none";
    EGLDisplay display = open_display(platform);
    if (display == EGL_NO_DISPLAY) {
        error = "egl: no surfaceless or device platform display is available";
        return nullptr;
    }
    EGLint major = 0, minor = 0;
    if (!eglInitialize(display, &major, &minor)) {
        error = "egl: eglInitialize failed on the " + std::string(platform) + " platform (" +
                egl_error_name(eglGetError()) + ")";
        return nullptr;
    }
    if (!eglBindAPI(EGL_OPENGL_API)) {
        error = "egl: the driver offers no desktop OpenGL API";
        eglTerminate(display);
        return nullptr;
    }
    const EGLint attribs[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 5,
                              EGL_CONTEXT_OPENGL_PROFILE_MASK,
                              EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_CONTEXT_OPENGL_DEBUG,
                              options.debug ? EGL_TRUE : EGL_FALSE, EGL_NONE};
    EGLContext context = eglCreateContext(display, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attribs);
    if (context == EGL_NO_CONTEXT) {
        error = "egl: could not create an OpenGL 4.5 core context on the " + std::string(platform) +
                " platform (" + egl_error_name(eglGetError()) + ")";
        // Ask the best core context the driver does give what it lacks.
        const EGLint probe_attribs[] = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_CONTEXT_MINOR_VERSION, 2,
                                        EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                        EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
        EGLContext probe = eglCreateContext(display, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, probe_attribs);
        if (probe != EGL_NO_CONTEXT) {
            if (eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, probe))
                error = describe_shortfall("egl", reinterpret_cast<GetProcAddress>(eglGetProcAddress)) +
                        " (" + platform + " platform)";
            eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
            eglDestroyContext(display, probe);
        }
        eglTerminate(display);
        return nullptr;
    }
    auto result = std::make_unique<EglContext>(display, context, options.debug, platform);
    error = result->init();
    if (!error.empty()) return nullptr;
    return result;
}

}  // namespace candela::detail
