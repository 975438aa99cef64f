#version 450 core
// Reflection probes: one captured face's depth turned into the distance from the probe to the
// surface each texel saw (REFLECTIONS_FAR where it saw none), the cube array the lookups march
// against for parallax (reflections_shading.glsl, probe_parallax). The faces are 90-degree
// views with an infinite far plane and reversed depth, depth = znear / (distance along the
// face's axis), and the texel (x, y) of the face's framebuffer is the texel (x, y) of its
// cube-map layer.
#include "effects/reflections/reflections_data.h"

layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = REFLECTIONS_FACE_DEPTH_UNIT) uniform sampler2D t_face_depth;
layout(binding = REFLECTIONS_DISTANCE_IMAGE, r32f) uniform writeonly imageCubeArray distances;
layout(location = 0) uniform int u_layer;    // 6 probe + face
layout(location = 1) uniform float u_znear;  // the faces' near plane

void main() {
    ivec2 size = textureSize(t_face_depth, 0);
    ivec2 px = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(px, size))) return;
    float depth = texelFetch(t_face_depth, px, 0).r;
    vec2 ndc = (vec2(px) + 0.5) / vec2(size) * 2.0 - 1.0;
    float d = depth > 0.0 ? u_znear / depth * sqrt(1.0 + dot(ndc, ndc)) : REFLECTIONS_FAR;
    imageStore(distances, ivec3(px, u_layer), vec4(d));
}
