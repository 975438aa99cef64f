#pragma once
// Mipmaps of an RGBA8 or sRGB8_ALPHA8 2D texture by one draw per level: level L-1, seen through a
// single-level view with a linear filter and clamp to edge, drawn over all of level L as a
// rectangle with texture coordinates 0 to 1 (shaders/post/mip_downsample.*).
//
// On Mesa this is what glGenerateTextureMipmap does: st_generate_mipmap blits level to level with
// a linear filter, and the blitter draws that rectangle with that sampler. The texels come out the
// same, byte for byte (tests/unit/test_gl_worker.cpp compares every level, linear and sRGB,
// power-of-two and other sizes). Two things differ:
// - glGenerateTextureMipmap holds Mesa's texture mutex, which every context sharing the texture
//   needs for its own texture calls, for the whole call; a draw holds it only briefly. So a worker
//   context (platform/gl_worker.hpp) can make mipmaps while the main context keeps drawing.
// - On llvmpipe the blitter's shaders are compiled again in every process (about 0.1 s per
//   format); this program is an ordinary one, which Mesa's shader cache keeps between runs.
#include <glad/gl.h>

namespace candela::gl {

// `texture`: immutable 2D storage of `levels` levels in `format` (GL_RGBA8 or GL_SRGB8_ALPHA8),
// level 0 filled. `program`: the "mip_downsample" program. Call in a context whose draw state is
// GL's default (no blending, depth or stencil test, scissor, culling or colour mask), such as a
// worker context's; the bindings it changes (program, vertex array, draw framebuffer, viewport,
// texture unit 0's 2D texture and sampler, GL_FRAMEBUFFER_SRGB) are restored.
void draw_mipmaps(GLuint program, GLuint texture, GLenum format, int width, int height, int levels);

}  // namespace candela::gl
