#version 450 core
// Homogeneous fog over the opaque image: a surface at distance d keeps exp(-sigma d) of its
// radiance and gains (1 - exp(-sigma d)) of the fog's; the sky (no depth) is left alone.
#include "common/scene_data.glsl"
#include "effects/fog/fog_data.h"

layout(binding = 0) uniform sampler2D t_depth;  // reversed-Z

layout(location = 0) out vec4 out_fog;  // blended: rgb added, the image scaled by alpha

void main() {
    float depth = texelFetch(t_depth, ivec2(gl_FragCoord.xy), 0).r;
    if (depth <= 0.0) discard;
    vec4 pw = frame.inv_view_proj * vec4(gl_FragCoord.xy * frame.viewport.zw * 2.0 - 1.0, depth, 1.0);
    float d = distance(pw.xyz / pw.w, frame.camera_pos.xyz);
    float t = exp(-fog.colour_density.a * d);
    out_fog = vec4(fog.colour_density.rgb * (1.0 - t), t);
}
