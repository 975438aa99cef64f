#version 450 core
// Copies a texture of the viewport's size: the blend state of the pass does the compositing
// (depth peeling's front-to-back UNDER, then the result OVER the opaque image).
#include "gpu/bindings.h"
layout(binding = SOURCE_UNIT) uniform sampler2D t_source;
layout(location = 0) out vec4 out_color;
void main() { out_color = texelFetch(t_source, ivec2(gl_FragCoord.xy), 0); }
