// G-buffer layout of the deferred path (engine/render/passes/gbuffer.cpp allocates it):
//   0  RGBA8         base colour (sRGB-encoded here: 8 bits where the eye needs them), a occlusion
//   1  RGBA16F       octahedral normal (xy), roughness, metallic
//   2  RGBA16F       dielectric F0 (rgb) and F90 (a): KHR_materials_specular/_ior folded in
//   3  the light buffer (RGBA32F HDR target): emission
//   depth            DEPTH32F reversed-Z; the position is reconstructed from it, not stored
#include "../common/brdf.glsl"

// The sRGB transfer function (IEC 61966-2-1), encoded by hand rather than through an SRGB8
// attachment so that no framebuffer-sRGB state is involved.
vec3 gbuffer_encode_srgb(vec3 c) {
    c = saturate(c);
    return mix(c * 12.92, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(vec3(0.0031308), c));
}
vec3 gbuffer_decode_srgb(vec3 c) { return mix(c / 12.92, pow((c + 0.055) / 1.055, vec3(2.4)), step(vec3(0.04045), c)); }

// Octahedral normal encoding (Cigolle et al. 2014, "A Survey of Efficient Representations for
// Independent Unit Vectors").
vec2 oct_wrap(vec2 v) { return (1.0 - abs(v.yx)) * vec2(v.x >= 0.0 ? 1.0 : -1.0, v.y >= 0.0 ? 1.0 : -1.0); }
vec2 oct_encode(vec3 n) {
    n /= abs(n.x) + abs(n.y) + abs(n.z);
    return n.z >= 0.0 ? n.xy : oct_wrap(n.xy);
}
vec3 oct_decode(vec2 e) {
    vec3 n = vec3(e, 1.0 - abs(e.x) - abs(e.y));
    if (n.z < 0.0) n.xy = oct_wrap(n.xy);
    return normalize(n);
}

// The BRDF input whose dielectric_f0()/_f90() give back the stored F0 and F90 exactly: with
// ior 1.5 ((ior-1)/(ior+1))^2 = 0.04, and F0 <= F90 always holds for what the G-buffer stores.
BrdfInput gbuffer_brdf(vec4 base_occlusion, vec4 normal_rm, vec4 f0_f90) {
    BrdfInput b;
    b.base_color = gbuffer_decode_srgb(base_occlusion.rgb);
    b.roughness = normal_rm.z;
    b.metallic = normal_rm.w;
    b.ior = 1.5;
    b.specular_factor = f0_f90.a;
    b.specular_color = f0_f90.a > 0.0 ? f0_f90.rgb / (0.04 * f0_f90.a) : vec3(0.0);
#ifdef MATERIAL_LAYERS
    brdf_layers_off(b);
#endif
    return b;
}
