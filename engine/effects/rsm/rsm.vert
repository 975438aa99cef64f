#version 450 core
// Reflective shadow map: the forward vertex layout, projected by one light view.
#include "common/scene_data.glsl"
#include "lighting/material_uv.glsl"

layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec4 in_tangent;
layout(location = 3) in vec2 in_uv0;
layout(location = 4) in vec2 in_uv1;
layout(location = 5) in vec4 in_color;

layout(location = 0) uniform mat4 u_model;
layout(location = 1) uniform mat3 u_normal_matrix;
layout(location = 4) uniform mat4 u_view_proj;  // the light view

layout(location = 0) out vec3 v_world_pos;
layout(location = 1) out vec3 v_normal;
layout(location = 2) out vec4 v_tangent;
layout(location = 4) out vec4 v_color;

void main() {
    vec4 world = u_model * vec4(in_position, 1.0);
    v_world_pos = world.xyz;
    v_normal = u_normal_matrix * in_normal;
    v_tangent = vec4(mat3(u_model) * in_tangent.xyz, in_tangent.w);
    write_material_uvs(in_uv0, in_uv1);
    v_color = in_color;
    gl_Position = u_view_proj * world;
}
