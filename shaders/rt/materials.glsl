// The material at a tracer hit: BRDF inputs with their textures, emission, BLEND coverage,
// transmission, and the exact Fresnel term of a dielectric interface. Included after
// trace_common.glsl (it reads the scene's materials and textures).
#include "trace_common.glsl"
#ifdef MATERIAL_LAYERS
#include "../common/material_layers.glsl"
#endif

// The material at a hit, with its textures (base colour, metallic-roughness), as the forward pass
// reads them. Normal and occlusion maps are not used here: occlusion is what the tracer computes.
BrdfInput brdf_input(SurfaceHit s) {
    int mi = s.material;
    MaterialData m = materials[mi];
    BrdfInput b;
    b.base_color = m.base_color.rgb * s.color.rgb;
    b.metallic = saturate(m.metallic);
    b.roughness = saturate(m.roughness);
#ifndef RT_NO_TEXTURES
    if (m.texcoord.x >= 0)
        b.base_color *= material_texture(m, 0, m.images.x, m.texcoord.x, s.uv0, s.uv1).rgb;
    if (m.texcoord.y >= 0) {
        vec4 mr = material_texture(m, 1, m.images.y, m.texcoord.y, s.uv0, s.uv1);
        b.roughness *= mr.g;
        b.metallic *= mr.b;
    }
#endif
    b.ior = m.ior;
    b.specular_factor = m.specular_factor;
    b.specular_color = m.specular_color;
#ifdef MATERIAL_LAYERS
    float transmission = 0.0;
    material_layers(m, s.uv0, s.uv1, s.ni, s.t, s.b, b, transmission);
#endif
    return b;
}
vec3 surface_emission(SurfaceHit s) {
    MaterialData m = materials[s.material];
    vec3 e = m.emission;
#ifndef RT_NO_TEXTURES
    if (m.emissive_texcoord >= 0)
        e *= material_texture(m, 4, m.emissive_image, m.emissive_texcoord, s.uv0, s.uv1).rgb;
#endif
    return e;
}
bool material_double_sided(int mi) { return materials[mi].double_sided > 0.5; }

// alphaMode BLEND: the coverage the rasterizer blends with (SRC_ALPHA, ONE_MINUS_SRC_ALPHA); 1 for
// every other mode. Camera paths composite blended layers with it, in depth order, which is the
// exact answer sorted blending and depth peeling approximate. Shadow, AO and bounce rays treat
// blended surfaces as opaque, as the shadow maps do.
float blend_alpha(SurfaceHit s) {
    MaterialData m = materials[s.material];
    if (int(m.alpha_mode) != 2) return 1.0;
    float a = m.base_color.a * s.color.a;
#ifndef RT_NO_TEXTURES
    if (m.texcoord.x >= 0) a *= material_texture(m, 0, m.images.x, m.texcoord.x, s.uv0, s.uv1).a;
#endif
    return saturate(a);
}
float material_transmission(SurfaceHit s) {
    MaterialData m = materials[s.material];
#ifdef MATERIAL_LAYERS
    if (m.transmission > 0.0 && ext_image(m, EXT_TRANSMISSION) >= 0)
        return m.transmission * ext_texture(m, EXT_TRANSMISSION, s.uv0, s.uv1, false).r;
#endif
    return m.transmission;
}
#ifdef MATERIAL_LAYERS
// KHR_materials_unlit: the surface's colour, seen by every ray that hits it; it neither reflects
// nor is it sampled as a light.
bool surface_unlit(SurfaceHit s) { return material_unlit(materials[s.material]); }
vec3 unlit_color(SurfaceHit s) { return brdf_input(s).base_color; }
#endif
// KHR_materials_volume: thickness 0 is a thin wall (light passes without bending).
bool material_thin(int mi) { return materials[mi].thickness <= 0.0; }

// Light leaving a surface towards the viewer by emission: front side, or both if double-sided.
vec3 emitted(SurfaceHit s) {
    return (s.front || material_double_sided(s.material)) ? surface_emission(s) : vec3(0.0);
}

// ---- dielectric interfaces (exact Fresnel) ----------------------------------------------------

// Unpolarised Fresnel reflectance; eta = n_incident / n_transmitted. 1 for total internal reflection.
float fresnel_dielectric(float cos_i, float eta) {
    float sin2_t = eta * eta * max(0.0, 1.0 - cos_i * cos_i);
    if (sin2_t >= 1.0) return 1.0;
    float cos_t = sqrt(1.0 - sin2_t);
    float rs = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    float rp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    return 0.5 * (rs * rs + rp * rp);
}
