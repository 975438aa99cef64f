#version 450 core
// What a camera ray that hits nothing sees: the environment radiance.
#include "../common/scene_data.glsl"

layout(binding = ENVIRONMENT_UNIT) uniform sampler2D t_environment;
layout(location = 0) in vec2 v_ndc;
layout(location = 0) out vec4 out_radiance;

void main() {
    if (frame.debug_view != DEBUG_VIEW_NONE) {  // debug views: no light reaches the sky; nothing occludes it (AO 1)
        out_radiance = vec4(vec3(frame.debug_view == DEBUG_VIEW_OCCLUSION ? 1.0 : 0.0), 1.0);  // (indirect view: 0)
        return;
    }
    vec4 p = frame.inv_view_proj * vec4(v_ndc, 0.5, 1.0);
    vec3 dir = normalize(p.xyz / p.w - frame.camera_pos.xyz);
    vec3 radiance = frame.env_radiance.rgb;
    if (frame.env_map_bound > 0.5) radiance *= textureLod(t_environment, direction_to_equirect(dir), 0.0).rgb;
    out_radiance = vec4(radiance, 1.0);
}
