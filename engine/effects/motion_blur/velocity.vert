#version 450 core
// Motion blur, pass 1 (vertex): each vertex at the frame's time (what the image shows, depth
// tested), and at shutter open and close, projected with the frame's camera
// (GpuScene::motion_vertex_array(): attribute 0 the position at the frame's time, 1 at open, 2 at
// close, object space; the draw's model matrices at those times in the uniforms).
#include "common/scene_data.glsl"

layout(location = 0) in vec3 a_now;
layout(location = 1) in vec3 a_open;
layout(location = 2) in vec3 a_close;

layout(location = 0) uniform mat4 u_model;
layout(location = 1) uniform mat4 u_model_open;
layout(location = 2) uniform mat4 u_model_close;

layout(location = 0) out vec4 v_open;   // clip space at shutter open
layout(location = 1) out vec4 v_close;  // and at close

void main() {
    gl_Position = frame.view_proj * (u_model * vec4(a_now, 1.0));
    v_open = frame.view_proj * (u_model_open * vec4(a_open, 1.0));
    v_close = frame.view_proj * (u_model_close * vec4(a_close, 1.0));
}
