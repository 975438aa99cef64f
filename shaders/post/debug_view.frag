#version 450 core
// The viewer's buffer inspector: one channel or all of a frame-graph texture, a layer of an
// array (shadow maps, reflective shadow maps) or a probe cube unwrapped to longitude/latitude,
// scaled, then sRGB-encoded for the window.
#include "gpu/bindings.h"
#include "../common/math.glsl"

layout(location = 0) in vec2 v_uv;
layout(location = 0) out vec4 out_color;
layout(binding = DEBUG_2D_UNIT) uniform sampler2D t_2d;
layout(binding = DEBUG_ARRAY_UNIT) uniform sampler2DArray t_array;
layout(binding = DEBUG_CUBE_UNIT) uniform samplerCubeArray t_cube;
layout(location = 0) uniform int u_kind;     // 0 2D, 1 2D array, 2 cube-map array
layout(location = 1) uniform int u_channel;  // 0 rgb, 1 r, 2 g, 3 b, 4 a
layout(location = 2) uniform float u_scale;
layout(location = 3) uniform int u_layer;
layout(location = 4) uniform float u_lod;

void main() {
    vec4 v;
    if (u_kind == 0) {
        v = textureLod(t_2d, v_uv, u_lod);
    } else if (u_kind == 1) {
        v = textureLod(t_array, vec3(v_uv, float(u_layer)), u_lod);
    } else {
        // Longitude/latitude: u from -pi to pi about +Y (as direction_to_equirect), v from top.
        float phi = (v_uv.x - 0.5) * 2.0 * PI, theta = (1.0 - v_uv.y) * PI;
        vec3 d = vec3(sin(theta) * sin(phi), cos(theta), -sin(theta) * cos(phi));
        v = textureLod(t_cube, vec4(d, float(u_layer)), u_lod);
    }
    vec3 c = u_channel == 0 ? v.rgb : vec3(v[u_channel - 1]);
    c = clamp(c * u_scale, 0.0, 1.0);
    // sRGB encoding (the window's framebuffer is not sRGB).
    c = mix(c * 12.92, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(0.0031308, c));
    out_color = vec4(c, 1.0);
}
