// The material at a raster fragment (glTF textures, alpha mode, normal map), shared by the
// forward shading and the G-buffer pass so that both see exactly the same surface.
// Expects the varyings of forward/forward.vert (texture coordinates: lighting/material_uv.glsl)
// and the per-draw uniforms below.
#include "../common/brdf.glsl"
#include "gpu/bindings.h"

layout(location = 2) uniform int u_material;
layout(location = 3) uniform int u_mirrored;  // 1 when the model matrix has a negative determinant

layout(binding = BASE_COLOR_UNIT) uniform sampler2D t_base_color;
layout(binding = METALLIC_ROUGHNESS_UNIT) uniform sampler2D t_metallic_roughness;
layout(binding = NORMAL_UNIT) uniform sampler2D t_normal;
layout(binding = OCCLUSION_UNIT) uniform sampler2D t_occlusion;
layout(binding = EMISSIVE_UNIT) uniform sampler2D t_emissive;

layout(location = 0) centroid in vec3 v_world_pos;
layout(location = 1) centroid in vec3 v_normal;
layout(location = 2) centroid in vec4 v_tangent;
layout(location = 4) centroid in vec4 v_color;
// Per texture slot: its texcoord set and KHR_texture_transform applied in the vertex stage
// (lighting/material_uv.glsl explains why: helper lanes read 0 from the materials SSBO on llvmpipe).
layout(location = 3) centroid in vec4 v_slot_uv01;  // xy base colour, zw metallic-roughness
layout(location = 5) centroid in vec4 v_slot_uv23;  // xy normal, zw occlusion
layout(location = 6) centroid in vec2 v_slot_uv4;  // emissive
layout(location = 7) flat in int v_material_bits;  // bits 0-4: slot textured, bit 5: alpha MASK
// 1 from every vertex (lighting/material_uv.glsl), interpolated like the inputs above. With
// multisampling, Mesa's llvmpipe (22.3) computes a perspective-correct centroid input as value / w
// interpolated at the centroid times w at the pixel centre: where the centre lies outside the
// triangle every such input is scaled by w_centre / w_centroid. That factor is close to 1 on a
// surface seen face-on, but w at the centre is that of the triangle's plane extended, and where
// the plane is seen edge-on (a box's side at grazing view) the centre can lie near or beyond its
// horizon: the factor was -149 on one edge pixel, which scaled the colour to -69 and turned the
// normal around (a negative pixel), and a factor of a few per mille already moves the position
// millimetres off the surface, enough for a light a few centimetres away to find the receiver
// behind its own surface in the shadow map. This 1 carries the same factor, so every centroid
// input divided by it (the accessors below; nothing reads the inputs directly) is its value at the
// centroid, inside the triangle, on any driver (where interpolation is right, a division by 1).
layout(location = 8) centroid in float v_one;
#ifdef MATERIAL_LAYERS
layout(location = 9) centroid in vec4 v_uv01;
vec4 in_uv01() { return v_uv01 / v_one; }
layout(binding = MATERIAL_IMAGES_UNIT) uniform sampler2DArray t_images;
layout(binding = MATERIAL_IMAGES_SRGB_UNIT) uniform sampler2DArray t_images_srgb;
#include "../common/material_layers.glsl"
#endif

vec3 in_world_pos() { return v_world_pos / v_one; }
vec3 in_normal() { return v_normal / v_one; }
vec4 in_tangent() { return v_tangent / v_one; }  // w: the handedness sign
vec4 in_color() { return v_color / v_one; }
vec4 in_slot_uv01() { return v_slot_uv01 / v_one; }
vec4 in_slot_uv23() { return v_slot_uv23 / v_one; }
vec2 in_slot_uv4() { return v_slot_uv4 / v_one; }

struct Surface {
    BrdfInput brdf;
    vec3 p;          // world position: the receiver of lights and shadows (v_one above)
    vec3 n;          // shading normal (normal-mapped, facing the viewer's side)
    float occlusion;
    vec3 emission;
    float alpha;
    int alpha_mode;  // 0 opaque, 1 mask, 2 blend
    float transmission;  // KHR_materials_transmission factor
    bool thin;           // thin-walled (KHR_materials_volume thickness 0)
    bool unlit;          // KHR_materials_unlit: the colour is base_color
};

#ifdef NO_MATERIAL_TEXTURES
bool slot_textured(int slot) { return false; }  // no material has a texture (forward/forward.frag)
#else
bool slot_textured(int slot) { return (v_material_bits & (1 << slot)) != 0; }
#endif

// Texture reads use implicit derivatives, which are defined only in uniform control flow and
// which the helper lanes of a quad take part in. So every read below happens before any branch
// on per-fragment values or on data read from the materials SSBO (0 in helper lanes on
// llvmpipe), and before the alpha-mask discard; the branches around them depend only on the flat
// material bits, which every lane of the draw sees.

// Alpha mode MASK: discards fragments below the cutoff (the shadow pass needs only this).
void alpha_test() {
    if ((v_material_bits & 32) == 0) return;
    float a = slot_textured(0) ? texture(t_base_color, in_slot_uv01().xy).a : 1.0;
    MaterialData m = materials[u_material];
    if (m.base_color.a * in_color().a * a < m.alpha_cutoff) discard;
}

// Alpha to coverage (forward with multisampling, aa.alpha_to_coverage): a MASK fragment is not
// discarded at the cutoff but gets the coverage alpha (a - cutoff) / fwidth(a) + 0.5, clamped,
// which the rasterizer turns into the share of samples it covers: the cutoff's contour is then
// anti-aliased like a triangle edge, within a pixel of it (Golus 2017, "Anti-aliased alpha test").
bool g_alpha_to_coverage = false;

// NDF filtering (multisampled frames, aa.specular_filter): a lobe much narrower than the normal's
// turn over a pixel gives a highlight smaller than the pixel, which the few shading points of
// MSAA hit or miss (a single hit weighs a quarter of the pixel with a peak hundreds of times the
// pixel's mean). The normals over the pixel's filter (variance frame.specular_filter, pixels^2)
// spread like a lobe of alpha^2 = 2 variance |dn|^2, which adds to the material's alpha^2, capped
// at 0.18 so that silhouettes of coarse meshes do not turn matte (Tokuyoshi and Kaplanyan 2021,
// "Stable geometric specular antialiasing with projected-space NDF filtering", JCGT 10(2)).
float filtered_roughness(float roughness, float normal_turn2) {
    float a2 = roughness * roughness * roughness * roughness;
    a2 = min(a2 + min(2.0 * frame.specular_filter * normal_turn2, 0.18), 1.0);
    return sqrt(sqrt(a2));
}

// Evaluates the material; discards masked-out fragments.
Surface fragment_surface() {
    vec4 tex_base = slot_textured(0) ? texture(t_base_color, in_slot_uv01().xy) : vec4(1.0);
    vec4 tex_mr = slot_textured(1) ? texture(t_metallic_roughness, in_slot_uv01().zw) : vec4(1.0);
    vec3 tex_normal = slot_textured(2) ? texture(t_normal, in_slot_uv23().xy).xyz : vec3(0.5, 0.5, 1.0);
    float tex_occlusion = slot_textured(3) ? texture(t_occlusion, in_slot_uv23().zw).r : 1.0;
    vec3 tex_emission = slot_textured(4) ? texture(t_emissive, in_slot_uv4()).rgb : vec3(1.0);
    // How much the interpolated normal turns over the pixel (derivatives: uniform control flow).
    vec3 n_interp = normalize(in_normal());
    float normal_turn2 = dot(dFdx(n_interp), dFdx(n_interp)) + dot(dFdy(n_interp), dFdy(n_interp));

    MaterialData m = materials[u_material];
    Surface s;
    vec4 base = m.base_color * in_color() * tex_base;
    float alpha_width = fwidth(base.a);  // here: derivatives need uniform control flow
    s.alpha_mode = int(m.alpha_mode);
    s.alpha = base.a;

    float metallic = m.metallic;
    float roughness = m.roughness;
    roughness *= tex_mr.g;
    metallic *= tex_mr.b;

    vec3 n = normalize(in_normal());
    // Mirrored nodes are drawn with reversed winding, so gl_FrontFacing already accounts for them.
    if (!gl_FrontFacing) n = -n;
#ifdef MATERIAL_LAYERS
    // The frame of the interpolated normal, for the layers (coat normal map, anisotropy).
    vec3 ni = n, ti, bi_;
    {
        vec4 tangent = in_tangent();
        vec3 t = tangent.xyz - n * dot(n, tangent.xyz);
        float tl = length(t);
        if (tl > 1e-8) {
            ti = t / tl;
            bi_ = cross(n, ti) * (tangent.w < 0.0 ? -1.0 : 1.0) * (gl_FrontFacing ? 1.0 : -1.0) * (u_mirrored != 0 ? -1.0 : 1.0);
        } else {
            onb(n, ti, bi_);
        }
    }
#endif
    if (slot_textured(2)) {
        vec4 tangent = in_tangent();
        vec3 t = tangent.xyz - n * dot(n, tangent.xyz);
        float tl = length(t);
        if (tl > 1e-8) {
            t /= tl;
            // A mirroring model matrix reverses the handedness of the transformed frame.
            vec3 b = cross(n, t) * (tangent.w < 0.0 ? -1.0 : 1.0) * (gl_FrontFacing ? 1.0 : -1.0) *
                     (u_mirrored != 0 ? -1.0 : 1.0);
            vec3 tn = tex_normal * 2.0 - 1.0;
            tn.xy *= m.normal_scale;
            vec3 mapped = mat3(t, b, n) * tn;
            float ml = length(mapped);
            if (ml > 1e-8) n = mapped / ml;
        }
    }
    s.occlusion = slot_textured(3) ? mix(1.0, tex_occlusion, m.occlusion_strength) : 1.0;
    s.emission = m.emission * tex_emission;

    s.brdf.base_color = base.rgb;
    s.brdf.metallic = saturate(metallic);
    s.brdf.roughness = saturate(roughness);
    s.brdf.ior = m.ior;
    s.brdf.specular_factor = m.specular_factor;
    s.brdf.specular_color = m.specular_color;
    s.transmission = m.transmission;
    s.thin = m.thickness <= 0.0;
    s.unlit = false;
#ifdef MATERIAL_LAYERS
    material_layers(m, in_uv01().xy, in_uv01().zw, ni, ti, bi_, s.brdf, s.transmission);
    s.unlit = material_unlit(m);
#endif

    if (frame.specular_filter > 0.0) {
        s.brdf.roughness = filtered_roughness(s.brdf.roughness, normal_turn2);
#ifdef MATERIAL_LAYERS
        s.brdf.clearcoat_roughness = filtered_roughness(s.brdf.clearcoat_roughness, normal_turn2);
#endif
    }

    s.p = in_world_pos();
    // Shading normals facing away from the viewer are bent back to the horizon.
    vec3 v = normalize(frame.camera_pos.xyz - s.p);
    float nv = dot(n, v);
    if (nv < 1e-4) n = normalize(n + v * (1e-4 - nv));
    s.n = n;
    if (s.alpha_mode == 1) {
        if (g_alpha_to_coverage) {
            s.alpha = clamp((base.a - m.alpha_cutoff) / max(alpha_width, 1e-4) + 0.5, 0.0, 1.0);
            if (s.alpha <= 0.0) discard;
        } else if (base.a < m.alpha_cutoff)
            discard;
    }
    return s;
}
