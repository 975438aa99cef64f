#include "gl/mipmaps.hpp"

#include <algorithm>

namespace candela::gl {

void blit_mipmaps(GLuint texture, int width, int height, int levels, bool srgb) {
    if (levels < 2) return;
    GLuint fbo[2] = {0, 0};
    glCreateFramebuffers(2, fbo);
    // With GL_FRAMEBUFFER_SRGB on, a blit between sRGB images decodes, filters and encodes (GL 4.5
    // core, 18.3.1); off, it would filter the encoded values.
    const GLboolean was_srgb = glIsEnabled(GL_FRAMEBUFFER_SRGB);
    if (srgb && !was_srgb) glEnable(GL_FRAMEBUFFER_SRGB);
    int w = width, h = height;
    for (int level = 1; level < levels; ++level) {
        const int nw = std::max(w / 2, 1), nh = std::max(h / 2, 1);
        glNamedFramebufferTexture(fbo[0], GL_COLOR_ATTACHMENT0, texture, level - 1);
        glNamedFramebufferTexture(fbo[1], GL_COLOR_ATTACHMENT0, texture, level);
        glNamedFramebufferReadBuffer(fbo[0], GL_COLOR_ATTACHMENT0);
        glNamedFramebufferDrawBuffer(fbo[1], GL_COLOR_ATTACHMENT0);
        glBlitNamedFramebuffer(fbo[0], fbo[1], 0, 0, w, h, 0, 0, nw, nh, GL_COLOR_BUFFER_BIT, GL_LINEAR);
        w = nw;
        h = nh;
    }
    if (srgb && !was_srgb) glDisable(GL_FRAMEBUFFER_SRGB);
    glDeleteFramebuffers(2, fbo);
}

}  // namespace candela::gl
