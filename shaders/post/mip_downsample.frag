#version 450 core
// One mip level from the level above it (gl/mipmaps.hpp): a bilinear sample of a single-level
// view of level L-1, clamped to its edges, written to level L. For an sRGB texture the view
// decodes and GL_FRAMEBUFFER_SRGB encodes, as a blit does.
#include "gpu/bindings.h"
layout(binding = SOURCE_UNIT) uniform sampler2D t_source;
layout(location = 0) in vec2 v_uv;
layout(location = 0) out vec4 out_color;
void main() { out_color = texture(t_source, v_uv); }
