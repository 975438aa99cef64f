#version 450 core
// Forward PBR shading: every light per pixel (with its shadow), emission, environment ambient.
#include "../common/scene_data.glsl"
#include "../lighting/surface.glsl"
#include "../lighting/shading.glsl"

layout(location = 0) out vec4 out_radiance;

void main() {
    Surface s = fragment_surface();
    vec3 v = normalize(frame.camera_pos.xyz - v_world_pos);
    vec2 pixel = gl_FragCoord.xy;
    if (frame.debug.x == 3) {
        out_radiance = vec4(rsm_indirect(s.brdf, pixel, v_world_pos), 1.0);
        return;
    }
    if (frame.debug.x != 0) {
        float value = frame.debug.x == 1 ? light_visibility(v_world_pos, s.n, pixel) : ssao_at(pixel);
        out_radiance = vec4(vec3(value), 1.0);
        return;
    }
    vec3 color = s.emission;
    for (int i = 0; i < frame.counts.x; ++i) color += shade_light(i, s.brdf, v_world_pos, s.n, v, pixel);
    color += shade_ambient(s.brdf, s.n, v, s.occlusion * ssao_at(pixel));
    color += rsm_indirect(s.brdf, pixel, v_world_pos);
    out_radiance = vec4(color, s.alpha_mode == 2 ? s.alpha : 1.0);
}
