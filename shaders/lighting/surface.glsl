// The material at a raster fragment (glTF textures, alpha mode, normal map), shared by the
// forward shading and the G-buffer pass so that both see exactly the same surface.
// Expects the varyings of forward/forward.vert and the per-draw uniforms below.
#include "../common/brdf.glsl"

layout(location = 2) uniform int u_material;
layout(location = 3) uniform int u_mirrored;  // 1 when the model matrix has a negative determinant

layout(binding = 0) uniform sampler2D t_base_color;
layout(binding = 1) uniform sampler2D t_metallic_roughness;
layout(binding = 2) uniform sampler2D t_normal;
layout(binding = 3) uniform sampler2D t_occlusion;
layout(binding = 4) uniform sampler2D t_emissive;

layout(location = 0) in vec3 v_world_pos;
layout(location = 1) in vec3 v_normal;
layout(location = 2) in vec4 v_tangent;
layout(location = 3) in vec4 v_uv;
layout(location = 4) in vec4 v_color;

struct Surface {
    BrdfInput brdf;
    vec3 n;          // shading normal (normal-mapped, facing the viewer's side)
    float occlusion;
    vec3 emission;
    float alpha;
    int alpha_mode;  // 0 opaque, 1 mask, 2 blend
    float transmission;  // KHR_materials_transmission factor
    bool thin;           // thin-walled (KHR_materials_volume thickness 0)
};

vec2 slot_uv(MaterialData m, int slot, int set) {
    vec3 uv = vec3(set == 1 ? v_uv.zw : v_uv.xy, 1.0);
    return vec2(dot(m.uv_transform[slot * 2].xyz, uv), dot(m.uv_transform[slot * 2 + 1].xyz, uv));
}

// Alpha mode MASK: discards fragments below the cutoff (the shadow pass needs only this).
void alpha_test() {
    MaterialData m = materials[u_material];
    if (int(m.params.z) != 1) return;
    float a = m.base_color.a * v_color.a;
    if (m.texcoord.x >= 0) a *= texture(t_base_color, slot_uv(m, 0, m.texcoord.x)).a;
    if (a < m.params.y) discard;
}

// Evaluates the material; discards masked-out fragments.
Surface fragment_surface() {
    MaterialData m = materials[u_material];
    Surface s;
    vec4 base = m.base_color * v_color;
    if (m.texcoord.x >= 0) base *= texture(t_base_color, slot_uv(m, 0, m.texcoord.x));
    s.alpha_mode = int(m.params.z);
    if (s.alpha_mode == 1 && base.a < m.params.y) discard;
    s.alpha = base.a;

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
    s.occlusion = 1.0;
    if (m.texcoord.w >= 0) s.occlusion = mix(1.0, texture(t_occlusion, slot_uv(m, 3, m.texcoord.w)).r, m.params2.w);
    s.emission = m.emission_metallic.rgb;
    if (m.texcoord2.x >= 0) s.emission *= texture(t_emissive, slot_uv(m, 4, m.texcoord2.x)).rgb;

    s.brdf.base_color = base.rgb;
    s.brdf.metallic = saturate(metallic);
    s.brdf.roughness = saturate(roughness);
    s.brdf.ior = m.params2.x;
    s.brdf.specular_factor = m.specular.a;
    s.brdf.specular_color = m.specular.rgb;
    s.transmission = m.params2.y;
    s.thin = m.volume.x <= 0.0;

    // Shading normals facing away from the viewer are bent back to the horizon.
    vec3 v = normalize(frame.camera_pos.xyz - v_world_pos);
    float nv = dot(n, v);
    if (nv < 1e-4) n = normalize(n + v * (1e-4 - nv));
    s.n = n;
    return s;
}
