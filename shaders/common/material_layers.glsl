// The material extensions' values at a surface point, shared by the rasterizer
// (lighting/surface.glsl) and the tracer (rt/materials.glsl) so that both shade the same layers.
// Their textures (the EXT_* slots of gpu/scene_blocks.h) are read from the scene's image array at
// level 0 in both: the includer declares it as t_images and t_images_srgb (sampler2DArray).
// Compiled only with MATERIAL_LAYERS (brdf.glsl).
#include "sampling.glsl"

int ext_image(MaterialData m, int slot) { return m.ext_image[slot / 4][slot % 4]; }
vec4 ext_texture(MaterialData m, int slot, vec2 uv0, vec2 uv1, bool srgb) {
    int set = m.ext_texcoord[slot / 4][slot % 4];
    vec3 uv = vec3(set == 1 ? uv1 : uv0, 1.0);
    vec3 at = vec3(dot(m.ext_uv_transform[slot * 2].xyz, uv), dot(m.ext_uv_transform[slot * 2 + 1].xyz, uv),
                   float(ext_image(m, slot)));
    return srgb ? textureLod(t_images_srgb, at, 0.0) : textureLod(t_images, at, 0.0);
}
// The slot's texture, or `none` when the slot has no texture.
vec4 ext_or(MaterialData m, int slot, vec2 uv0, vec2 uv1, bool srgb, vec4 none) {
    return ext_image(m, slot) >= 0 ? ext_texture(m, slot, uv0, uv1, srgb) : none;
}

bool material_unlit(MaterialData m) { return m.clearcoat.w > 0.5; }

// Fills the layers of `b` (base inputs already set) and scales `transmission` by its texture.
// ni: the interpolated normal (the coat's, unless the coat has its own normal map), t and b_: the
// unit tangent frame around it (the tangent's handedness applied).
void material_layers(MaterialData m, vec2 uv0, vec2 uv1, vec3 ni, vec3 t, vec3 b_, inout BrdfInput b,
                     inout float transmission) {
    brdf_layers_off(b);
    b.specular_factor *= ext_or(m, EXT_SPECULAR, uv0, uv1, false, vec4(1.0)).a;
    b.specular_color *= ext_or(m, EXT_SPECULAR_COLOR, uv0, uv1, true, vec4(1.0)).rgb;
    transmission *= ext_or(m, EXT_TRANSMISSION, uv0, uv1, false, vec4(1.0)).r;

    if (m.clearcoat.x > 0.0) {
        b.clearcoat = m.clearcoat.x * ext_or(m, EXT_CLEARCOAT, uv0, uv1, false, vec4(1.0)).r;
        b.clearcoat_roughness = saturate(m.clearcoat.y * ext_or(m, EXT_CLEARCOAT_ROUGHNESS, uv0, uv1, false, vec4(1.0)).g);
        b.coat_n = ni;
        if (ext_image(m, EXT_CLEARCOAT_NORMAL) >= 0) {
            vec3 tn = ext_texture(m, EXT_CLEARCOAT_NORMAL, uv0, uv1, false).xyz * 2.0 - 1.0;
            tn.xy *= m.clearcoat.z;
            vec3 mapped = mat3(t, b_, ni) * tn;
            if (dot(mapped, mapped) > 1e-16) b.coat_n = normalize(mapped);
        }
    }
    if (max(m.sheen.r, max(m.sheen.g, m.sheen.b)) > 0.0) {
        b.sheen_color = m.sheen.rgb * ext_or(m, EXT_SHEEN_COLOR, uv0, uv1, true, vec4(1.0)).rgb;
        b.sheen_roughness = saturate(m.sheen.a * ext_or(m, EXT_SHEEN_ROUGHNESS, uv0, uv1, false, vec4(1.0)).a);
    }
    if (m.anisotropy.x > 0.0) {
        // Direction in the tangent frame: the texture's (RG in [-1, 1]) rotated by the rotation.
        vec2 dir = vec2(1.0, 0.0);
        float strength = m.anisotropy.x;
        if (ext_image(m, EXT_ANISOTROPY) >= 0) {
            vec3 a = ext_texture(m, EXT_ANISOTROPY, uv0, uv1, false).rgb;
            dir = a.rg * 2.0 - 1.0;
            strength *= a.b;
            dir = dot(dir, dir) > 1e-12 ? normalize(dir) : vec2(1.0, 0.0);
        }
        vec2 rotated = vec2(m.anisotropy.y * dir.x - m.anisotropy.z * dir.y, m.anisotropy.z * dir.x + m.anisotropy.y * dir.y);
        b.anisotropy = saturate(strength);
        b.aniso_t = normalize(t * rotated.x + b_ * rotated.y);
    }
    if (m.iridescence.x > 0.0) {
        b.iridescence = m.iridescence.x * ext_or(m, EXT_IRIDESCENCE, uv0, uv1, false, vec4(1.0)).r;
        b.iridescence_ior = m.iridescence.y;
        b.iridescence_thickness = ext_image(m, EXT_IRIDESCENCE_THICKNESS) >= 0
            ? mix(m.iridescence.z, m.iridescence.w, ext_texture(m, EXT_IRIDESCENCE_THICKNESS, uv0, uv1, false).g)
            : m.iridescence.w;
    }
}
