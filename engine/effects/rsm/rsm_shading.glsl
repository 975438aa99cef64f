// What RSM adds to the lighting (included by shaders/lighting/shading.glsl through the registry):
// the gathered one-bounce irradiance, reflected by the Lambert part (hook indirect_light).
#include "effects/rsm/rsm_data.h"

layout(binding = RSM_INDIRECT_UNIT) uniform sampler2D t_rsm_indirect;  // bound when rsm.on = 1 (camera views only)
// One-bounce diffuse light from the reflective shadow maps, reflected by the Lambert part. A
// gather at lower resolution is upsampled geometry-aware: the four nearest gather samples
// weighted bilinearly and by how close their view depth (alpha) is to this pixel's, so light
// does not leak across silhouettes (joint bilateral upsampling, Kopf et al. 2007).
vec3 rsm_indirect_light(BrdfInput bi, vec3 p, vec3 n, vec3 v, vec2 pixel, float occlusion, float transmission) {
#ifdef RSM_OFF
    return vec3(0.0);  // rsm.on 0 (rsm.cpp): no gather to read
#else
    if (rsm.on == 0 || frame.camera_view == 0) return vec3(0.0);
    int f = max(rsm.downscale, 1);
    vec3 E;
    if (f == 1) {
        E = texelFetch(t_rsm_indirect, ivec2(pixel), 0).rgb;
    } else {
        // Gather sample i was computed at full-resolution pixel i * f (centre i * f + 0.5).
        float z = (frame.view * vec4(p, 1.0)).z;
        vec2 lo = (pixel - 0.5) / float(f);
        ivec2 base = ivec2(floor(lo));
        vec2 t = lo - vec2(base);
        ivec2 size = textureSize(t_rsm_indirect, 0);
        vec3 sum = vec3(0.0);
        float wsum = 0.0;
        for (int j = 0; j < 2; ++j)
            for (int i = 0; i < 2; ++i) {
                vec4 s = texelFetch(t_rsm_indirect, clamp(base + ivec2(i, j), ivec2(0), size - 1), 0);
                float wb = (i == 0 ? 1.0 - t.x : t.x) * (j == 0 ? 1.0 - t.y : t.y);
                float w = wb / (1e-3 + abs(s.a - z) / max(abs(z), 1e-30));
                sum += s.rgb * w;
                wsum += w;
            }
        E = wsum > 0.0 ? sum / wsum : vec3(0.0);
    }
    return bi.base_color * (1.0 - bi.metallic) * INV_PI * E;
#endif
}
