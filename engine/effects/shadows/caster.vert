#version 450 core
// Shadow-map pass: the forward vertex layout, projected by one shadow view.
// CASTER_DEPTH_ONLY (the "shadow_depth" program, for casters that are not alpha-masked): the
// position only. gl_Position is the same expression in both variants, so the depth they write
// is the same.
#include "common/scene_data.glsl"
#ifndef CASTER_DEPTH_ONLY
#include "lighting/material_uv.glsl"
#endif

layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec4 in_tangent;
layout(location = 3) in vec2 in_uv0;
layout(location = 4) in vec2 in_uv1;
layout(location = 5) in vec4 in_color;

layout(location = 0) uniform mat4 u_model;
layout(location = 4) uniform mat4 u_view_proj;  // the shadow view

#ifdef CASTER_DEPTH_ONLY
void main() {
    vec4 world = u_model * vec4(in_position, 1.0);
    gl_Position = u_view_proj * world;
}
#else
layout(location = 0) out vec3 v_world_pos;
layout(location = 1) out vec3 v_normal;
layout(location = 2) out vec4 v_tangent;
layout(location = 4) out vec4 v_color;

void main() {
    vec4 world = u_model * vec4(in_position, 1.0);
    v_world_pos = world.xyz;
    v_normal = in_normal;
    v_tangent = in_tangent;
    write_material_uvs(in_uv0, in_uv1);
    v_color = in_color;
    gl_Position = u_view_proj * world;
}
#endif
