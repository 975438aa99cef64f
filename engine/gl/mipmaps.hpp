#pragma once
// Mipmaps of a 2D texture by one linear blit per level (glBlitNamedFramebuffer, level L-1 to L,
// whole levels, sRGB-correct). On Mesa this is the operation glGenerateTextureMipmap performs
// (st_generate_mipmap blits level to level with a linear filter), and the texels come out the
// same (tests/unit/test_gl_worker.cpp compares every level, byte for byte, for linear and sRGB
// RGBA8 of power-of-two and other sizes). What differs is the locking: glGenerateTextureMipmap
// holds Mesa's texture mutex, which every context sharing the texture needs for its own texture
// calls and state updates, for the whole call, and on llvmpipe the call includes compiling the
// blit shader (about 0.1 s); a blit holds it only briefly. So a worker context
// (platform/gl_worker.hpp) makes mipmaps this way while the main context keeps working.
#include <glad/gl.h>

namespace candela::gl {

// `texture`: immutable 2D storage of `levels` levels, level 0 filled; `srgb`: its format is sRGB
// (the blit then filters decoded values, as mipmap generation does). Leaves GL_FRAMEBUFFER_SRGB
// as it found it and binds no framebuffer.
void blit_mipmaps(GLuint texture, int width, int height, int levels, bool srgb);

}  // namespace candela::gl
