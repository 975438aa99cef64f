#version 450 core
// Depth of field, pass 1: the HDR colour and each pixel's signed circle of confusion (radius in
// pixels, negative in front of the focus plane) from its reversed-Z depth, by the thin-lens
// formula the tracer samples: diameter = 2 A |d - F| / d * H / (2 F tan(yfov / 2)).
#include "common/scene_data.glsl"
#include "effects/dof/dof_data.h"

layout(binding = DOF_IN_UNIT) uniform sampler2D t_hdr;
layout(binding = DOF_IN2_UNIT) uniform sampler2D t_depth;  // reversed Z, 0 = far

layout(location = 0) out vec4 out_color;

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    vec3 c = texelFetch(t_hdr, pixel, 0).rgb;
    float z = texelFetch(t_depth, pixel, 0).r;
    // 1 / view depth: depth_to_view gives view z (negative in front) as a ratio; at depth 0 of an
    // infinite projection it is 1 / 0 (the depth is infinite, 1/d = 0). Anything not finite or
    // behind the camera counts as infinitely far.
    vec4 k = frame.depth_to_view;
    float num = k.x * z + k.y, den = k.z * z + k.w;
    float inv_d = abs(num) > 1e-30 ? -den / num : 0.0;
    if (!(inv_d >= 0.0) || isinf(inv_d)) inv_d = isinf(inv_d) && inv_d > 0.0 ? 1e30 : 0.0;
    float s = dof.coc_scale * (1.0 - dof.focus * inv_d);
    s = clamp(s, -dof.max_radius, dof.max_radius);
    if (isnan(s)) s = 0.0;
    out_color = vec4(c, s);
}
