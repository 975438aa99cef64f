#include "gl/debug.hpp"

#include <glad/gl.h>

#include <atomic>
#include <string>

#include "core/log.hpp"

namespace candela::gl {
namespace {

std::atomic<int> g_errors{0};

void GLAD_API_PTR on_debug_message(GLenum source, GLenum type, GLuint id, GLenum severity,
                                   GLsizei length, const GLchar* message, const void*) {
    (void)source;
    (void)length;
    if (severity == GL_DEBUG_SEVERITY_NOTIFICATION) return;
    const std::string text = "GL debug (id " + std::to_string(id) + "): " + message;
    if (type == GL_DEBUG_TYPE_ERROR) {
        ++g_errors;
        log::warn("GL error: " + text);
    } else {
        log::debug(text);
    }
}

}  // namespace

void enable_debug_output() {
    if (!glDebugMessageCallback) return;
    glEnable(GL_DEBUG_OUTPUT);
    glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
    glDebugMessageCallback(on_debug_message, nullptr);
}

int debug_error_count() { return g_errors; }
void reset_debug_error_count() { g_errors = 0; }

}  // namespace candela::gl
