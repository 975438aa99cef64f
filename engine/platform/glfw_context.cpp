// A window for the viewer. Without an X display this fails with advice, never a crash.
#include <GLFW/glfw3.h>

#include <cstdlib>

#include "platform/context.hpp"

namespace candela::detail {
namespace {

std::string g_glfw_error;
void on_glfw_error(int, const char* description) { g_glfw_error = description ? description : ""; }

class GlfwContext final : public Context {
public:
    explicit GlfwContext(GLFWwindow* window) : window_(window) {}
    ~GlfwContext() override {
        glfwDestroyWindow(window_);
        glfwTerminate();
    }
    Backend backend() const override { return Backend::glfw; }
    bool make_current() override {
        glfwMakeContextCurrent(window_);
        std::string r, v;
        return load_gl_and_check("glfw", reinterpret_cast<GetProcAddress>(glfwGetProcAddress), r,
                                 v, false)
            .empty();
    }
    void swap_buffers() override { glfwSwapBuffers(window_); }
    GLFWwindow* window() override { return window_; }
    std::string init(bool debug, bool vsync) {
        glfwMakeContextCurrent(window_);
        glfwSwapInterval(vsync ? 1 : 0);
        return load_gl_and_check("glfw", reinterpret_cast<GetProcAddress>(glfwGetProcAddress),
                                 renderer_, version_, debug);
    }

private:
    GLFWwindow* window_;
};

}  // namespace

std::unique_ptr<Context> create_glfw(const ContextOptions& options, std::string& error) {
    glfwSetErrorCallback(on_glfw_error);
    if (!glfwInit()) {
        const char* display = std::getenv("DISPLAY");
        error = "glfw: cannot open a window (" + g_glfw_error + ")";
        if (!display || !*display)
            error += "; no X display is set: use 'candela render' for offscreen images, or run under xvfb-run";
        return nullptr;
    }
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 5);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    glfwWindowHint(GLFW_OPENGL_DEBUG_CONTEXT, options.debug ? GLFW_TRUE : GLFW_FALSE);
    glfwWindowHint(GLFW_VISIBLE, options.visible ? GLFW_TRUE : GLFW_FALSE);
    GLFWwindow* window =
        glfwCreateWindow(options.width, options.height, options.title.c_str(), nullptr, nullptr);
    if (!window) {
        error = "glfw: could not create an OpenGL 4.5 core window (" + g_glfw_error + ")";
        glfwTerminate();
        return nullptr;
    }
    auto result = std::make_unique<GlfwContext>(window);
    error = result->init(options.debug, options.vsync);
    if (!error.empty()) return nullptr;
    return result;
}

}  // namespace candela::detail
