#version 450 core
// Linear HDR radiance to display values: exposure + ACES fit + sRGB (the PNG/screen transform).
#include "gpu/bindings.h"
#include "../common/tonemap.glsl"

layout(binding = SOURCE_UNIT) uniform sampler2D t_hdr;
layout(location = 0) uniform float u_exposure_ev;
layout(location = 0) in vec2 v_uv;
layout(location = 0) out vec4 out_display;

void main() {
    vec3 radiance = texelFetch(t_hdr, ivec2(gl_FragCoord.xy), 0).rgb;
    // Non-finite radiance is shown as black rather than poisoning the display image.
    if (any(isnan(radiance)) || any(isinf(radiance))) radiance = vec3(0.0);
    out_display = vec4(display_transform(radiance, u_exposure_ev), 1.0);
}
