#version 450 core
// Motion blur, pass 1 (fragment): the screen-space motion of the visible surface point over the
// shutter, stored as McGuire et al.'s half vector V (pixels from the point's position at the
// centre of its motion to either end), its length clamped to motion_blur.max_radius.
// The clip positions at open and close are interpolated perspective-correctly with the
// barycentrics of the frame-time triangle: the same surface point at the two times.
#include "common/scene_data.glsl"
#include "effects/motion_blur/motion_blur_data.h"

layout(location = 0) in vec4 v_open;
layout(location = 1) in vec4 v_close;

layout(location = 0) out vec2 out_velocity;

void main() {
    // Behind the camera at open or close: no usable screen position, no blur.
    if (v_open.w <= 1e-6 || v_close.w <= 1e-6) {
        out_velocity = vec2(0.0);
        return;
    }
    vec2 a = v_open.xy / v_open.w, b = v_close.xy / v_close.w;
    vec2 half_motion = 0.25 * (b - a) * frame.viewport.xy;  // NDC spans 2 over the viewport; half of it
    float len = length(half_motion);
    if (!(len < 1e30)) half_motion = vec2(0.0), len = 0.0;  // NaN/Inf
    if (len > motion_blur.max_radius) half_motion *= motion_blur.max_radius / len;
    out_velocity = half_motion;
}
