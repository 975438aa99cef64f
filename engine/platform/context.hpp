#pragma once
// OpenGL 4.5 core contexts: EGL (surfaceless or device), OSMesa and a GLFW window.
// Creation never throws: an environment without usable GL is a result the caller reports
// (exit code 3 in the CLI).
#include <memory>
#include <optional>
#include <string>
#include <vector>

struct GLFWwindow;

namespace candela {

enum class Backend { auto_select, egl, osmesa, glfw };

const char* to_string(Backend backend);
std::optional<Backend> parse_backend(const std::string& name);

struct ContextOptions {
    int width = 16;   // window size for glfw; ignored by the headless backends (FBOs are used)
    int height = 16;
    bool debug = false;    // KHR_debug output, GL errors counted (on in tests)
    bool visible = true;   // glfw only
    bool vsync = true;     // glfw only
    std::string title = "Candela";
};

// A context that shares a Context's objects (textures, buffers, programs, syncs), for one worker
// thread (GlWorker). GL's entry points stay those loaded for the main context: the backends'
// are dispatch stubs that follow the calling thread's current context.
class SharedContext {
public:
    virtual ~SharedContext() = default;
    virtual bool make_current() = 0;  // on the calling thread
    virtual void release() = 0;       // current nowhere any more (call on the thread it is current on)
};

class Context {
public:
    virtual ~Context() = default;
    Context(const Context&) = delete;
    Context& operator=(const Context&) = delete;

    virtual Backend backend() const = 0;
    // Makes the context current on this thread and points the GL loader at its entry points.
    virtual bool make_current() = 0;
    virtual void swap_buffers() {}
    virtual GLFWwindow* window() { return nullptr; }
    // A context sharing this one's objects, current nowhere yet; null where the backend has none
    // (GLFW: a window's context is not made for this) or the driver refuses.
    virtual std::unique_ptr<SharedContext> create_shared() { return nullptr; }

    const std::string& renderer() const { return renderer_; }
    const std::string& version() const { return version_; }
    // "llvmpipe (LLVM 15.0.6, 256 bits) | 4.5 (Core Profile) Mesa 22.3.6"
    std::string device_string() const { return renderer_ + " | " + version_; }

protected:
    Context() = default;
    std::string renderer_;
    std::string version_;
};

struct ContextResult {
    std::unique_ptr<Context> context;
    std::string error;  // set when context is null: names the backend, the version got, the renderer
                        // and the features the driver lacks
    std::string notice;  // set when --backend auto fell back from EGL to OSMesa: says why
};

// auto_select tries EGL, then OSMesa.
ContextResult create_context(Backend backend, const ContextOptions& options = {});

namespace detail {
using GetProcAddress = void* (*)(const char*);
// Loads GL through glad with the backend's getProcAddress and checks for 4.5 core.
// Returns an empty string on success, else the reason.
// Which of Candela's required GL features a context of `version` (major * 10 + minor) with these
// extensions lacks: "GL_ARB_clip_control (reversed-Z depth), ..."; empty when none.
std::string missing_gl_features(int version, const std::vector<std::string>& extensions);
// For a context that is current but below 4.5: "<backend>: OpenGL 4.5 core is required; the
// driver offers '<version>' on '<renderer>'; missing: <features>".
std::string describe_shortfall(const char* backend, GetProcAddress get_proc);
std::string load_gl_and_check(const char* backend, GetProcAddress get_proc, std::string& renderer,
                              std::string& version, bool debug);
std::unique_ptr<Context> create_egl(const ContextOptions& options, std::string& error);
std::unique_ptr<Context> create_osmesa(const ContextOptions& options, std::string& error);
std::unique_ptr<Context> create_glfw(const ContextOptions& options, std::string& error);
}  // namespace detail

}  // namespace candela
