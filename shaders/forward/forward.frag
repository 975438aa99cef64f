#version 450 core
// Forward PBR shading: every punctual light per pixel, emission, environment ambient.
#include "../common/scene_data.glsl"
#include "../common/brdf.glsl"

layout(location = 2) uniform int u_material;
layout(location = 3) uniform int u_mirrored;  // 1 when the model matrix has a negative determinant

layout(binding = 0) uniform sampler2D t_base_color;
layout(binding = 1) uniform sampler2D t_metallic_roughness;
layout(binding = 2) uniform sampler2D t_normal;
layout(binding = 3) uniform sampler2D t_occlusion;
layout(binding = 4) uniform sampler2D t_emissive;
layout(binding = 5) uniform sampler2D t_environment;

layout(location = 0) in vec3 v_world_pos;
layout(location = 1) in vec3 v_normal;
layout(location = 2) in vec4 v_tangent;
layout(location = 3) in vec4 v_uv;
layout(location = 4) in vec4 v_color;

layout(location = 0) out vec4 out_radiance;

vec2 slot_uv(MaterialData m, int slot, int set) {
    vec3 uv = vec3(set == 1 ? v_uv.zw : v_uv.xy, 1.0);
    return vec2(dot(m.uv_transform[slot * 2].xyz, uv), dot(m.uv_transform[slot * 2 + 1].xyz, uv));
}

vec3 environment_specular(vec3 r, float roughness) {
    if (frame.env_radiance.w < 0.5) return frame.env_radiance.rgb;
    float lod = roughness * float(max(frame.counts.y - 1, 0));
    return frame.env_radiance.rgb * textureLod(t_environment, direction_to_equirect(r), lod).rgb;
}

vec3 environment_irradiance(vec3 n) {
    if (frame.env_radiance.w < 0.5) return PI * frame.env_radiance.rgb;
    return max(sh_irradiance(n), vec3(0.0));
}

void main() {
    MaterialData m = materials[u_material];
    vec4 base = m.base_color * v_color;
    if (m.texcoord.x >= 0) base *= texture(t_base_color, slot_uv(m, 0, m.texcoord.x));
    int alpha_mode = int(m.params.z);
    if (alpha_mode == 1 && base.a < m.params.y) discard;

    float metallic = m.emission_metallic.a;
    float roughness = m.params.x;
    if (m.texcoord.y >= 0) {
        vec4 mr = texture(t_metallic_roughness, slot_uv(m, 1, m.texcoord.y));
        roughness *= mr.g;
        metallic *= mr.b;
    }

    vec3 n = normalize(v_normal);
    // Mirrored nodes are drawn with reversed winding, so gl_FrontFacing already accounts for them.
    if (!gl_FrontFacing) n = -n;
    if (m.texcoord.z >= 0) {
        vec3 t = v_tangent.xyz - n * dot(n, v_tangent.xyz);
        float tl = length(t);
        if (tl > 1e-8) {
            t /= tl;
            // A mirroring model matrix reverses the handedness of the transformed frame.
            vec3 b = cross(n, t) * (v_tangent.w < 0.0 ? -1.0 : 1.0) * (gl_FrontFacing ? 1.0 : -1.0) *
                     (u_mirrored != 0 ? -1.0 : 1.0);
            vec3 tn = texture(t_normal, slot_uv(m, 2, m.texcoord.z)).xyz * 2.0 - 1.0;
            tn.xy *= m.params2.z;
            vec3 mapped = mat3(t, b, n) * tn;
            float ml = length(mapped);
            if (ml > 1e-8) n = mapped / ml;
        }
    }
    float occlusion = 1.0;
    if (m.texcoord.w >= 0)
        occlusion = mix(1.0, texture(t_occlusion, slot_uv(m, 3, m.texcoord.w)).r, m.params2.w);
    vec3 emission = m.emission_metallic.rgb;
    if (m.texcoord2.x >= 0) emission *= texture(t_emissive, slot_uv(m, 4, m.texcoord2.x)).rgb;

    BrdfInput bi;
    bi.base_color = base.rgb;
    bi.metallic = saturate(metallic);
    bi.roughness = saturate(roughness);
    bi.ior = m.params2.x;
    bi.specular_factor = m.specular.a;
    bi.specular_color = m.specular.rgb;

    vec3 v = normalize(frame.camera_pos.xyz - v_world_pos);
    // Shading normals facing away from the viewer are bent back to the horizon.
    float nv = dot(n, v);
    if (nv < 1e-4) n = normalize(n + v * (1e-4 - nv));

    vec3 color = emission;
    for (int i = 0; i < frame.counts.x; ++i) {
        vec3 l, E;
        float dist;
        light_incidence(lights[i], v_world_pos, l, E, dist);
        float NdotL = dot(n, l);
        if (NdotL <= 0.0) continue;
        color += brdf_eval(bi, n, l, v) * E * NdotL;
    }
    vec3 r = reflect(-v, n);
    color += occlusion * brdf_ambient(bi, n, v, environment_irradiance(n), environment_specular(r, bi.roughness));
    out_radiance = vec4(color, alpha_mode == 2 ? base.a : 1.0);
}
