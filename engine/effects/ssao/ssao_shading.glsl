// What SSAO adds to the lighting (included by shaders/lighting/shading.glsl through the registry):
// the occlusion of ambient and indirect light (hook occlusion).
#include "effects/ssao/ssao_data.h"

layout(binding = SSAO_UNIT) uniform sampler2D t_ssao;  // bound when ssao.on = 1 (camera views only)

// Screen-space ambient occlusion at a pixel (1 without the SSAO pass, and in views other than the
// camera's, such as probe faces). It scales ambient and environment light only, never direct light.
float ssao_occlusion(vec2 pixel) {
    if (ssao.on == 0 || frame.camera_view == 0) return 1.0;
    // AO texel i was computed at full-resolution pixel i * f (centre i * f + 0.5).
    float f = float(ssao.downscale);
    return texture(t_ssao, ((pixel - 0.5) / f + 0.5) / vec2(textureSize(t_ssao, 0))).r;
}
