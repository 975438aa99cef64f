#version 450 core
// The destination level as one rectangle, drawn as a 4-vertex triangle fan with texture
// coordinates from 0 to 1 at its corners: the geometry Mesa's blitter draws for a blit of a
// whole level (gl/mipmaps.hpp), so that the coordinates interpolate to the same values.
layout(location = 0) out vec2 v_uv;
void main() {
    const vec2 corners[4] = vec2[4](vec2(0.0, 0.0), vec2(1.0, 0.0), vec2(1.0, 1.0), vec2(0.0, 1.0));
    v_uv = corners[gl_VertexID];
    gl_Position = vec4(corners[gl_VertexID] * 2.0 - 1.0, 0.0, 1.0);
}
