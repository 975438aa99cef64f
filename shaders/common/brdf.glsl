// The one BRDF of Candela: glTF 2.0 metallic-roughness (glTF spec, Appendix B) with
// KHR_materials_specular and KHR_materials_ior. GGX distribution (Walter et al. 2007), height-
// correlated Smith visibility (Heitz 2014), Schlick Fresnel, Lambert diffuse. Used by the forward
// and deferred passes and by the ray tracer, so raster and reference shade identically.
#include "math.glsl"

struct BrdfInput {
    vec3 base_color;
    float metallic;
    float roughness;         // perceptual; alpha = roughness^2
    float ior;
    float specular_factor;   // KHR_materials_specular (0 => pure Lambert)
    vec3 specular_color;
#ifdef MATERIAL_LAYERS
    // The layers of the glTF material extensions (material_layers.glsl explains each; the
    // programs of a scene whose materials have none compile without them). brdf_layers_off()
    // sets the values that leave the base BRDF as it is.
    float clearcoat;             // KHR_materials_clearcoat weight
    float clearcoat_roughness;
    vec3 coat_n;                 // the coat's normal (world)
    vec3 sheen_color;            // KHR_materials_sheen (0: none)
    float sheen_roughness;
    float anisotropy;            // KHR_materials_anisotropy strength in [0, 1]
    vec3 aniso_t;                // the direction of anisotropy (world, in the shading plane)
    float iridescence;           // KHR_materials_iridescence weight
    float iridescence_ior;
    float iridescence_thickness; // nanometres
#endif
};

#ifdef MATERIAL_LAYERS
void brdf_layers_off(inout BrdfInput b) {
    b.clearcoat = 0.0;
    b.clearcoat_roughness = 0.0;
    b.coat_n = vec3(0.0, 0.0, 1.0);
    b.sheen_color = vec3(0.0);
    b.sheen_roughness = 0.0;
    b.anisotropy = 0.0;
    b.aniso_t = vec3(1.0, 0.0, 0.0);
    b.iridescence = 0.0;
    b.iridescence_ior = 1.3;
    b.iridescence_thickness = 0.0;
}
#endif

// Alpha is clamped away from 0 so that a perfect mirror under a point light stays finite.
float brdf_alpha(float roughness) { return max(roughness * roughness, 1e-3); }

float D_GGX(float NdotH, float alpha) {
    float a2 = alpha * alpha;
    float d = NdotH * NdotH * (a2 - 1.0) + 1.0;
    return a2 / (PI * d * d);
}

// V = G / (4 NdotL NdotV), height-correlated Smith-GGX.
float V_SmithGGXCorrelated(float NdotL, float NdotV, float alpha) {
    float a2 = alpha * alpha;
    float gv = NdotL * sqrt(NdotV * NdotV * (1.0 - a2) + a2);
    float gl = NdotV * sqrt(NdotL * NdotL * (1.0 - a2) + a2);
    float denom = gv + gl;
    return denom > 0.0 ? 0.5 / denom : 0.0;
}

vec3 F_Schlick(vec3 f0, vec3 f90, float VdotH) { return f0 + (f90 - f0) * pow5(1.0 - VdotH); }

// Dielectric reflectance at normal incidence and grazing (KHR_materials_specular, _ior).
vec3 dielectric_f0(BrdfInput m) {
    float r = (m.ior - 1.0) / (m.ior + 1.0);
    return min(vec3(r * r) * m.specular_color, vec3(1.0)) * m.specular_factor;
}
float dielectric_f90(BrdfInput m) { return m.specular_factor; }

// BRDF value f(l, v) (without the cosine), with the dielectric's diffuse lobe scaled by
// `diffuse_weight` (1 - transmission for a transmissive raster surface). n, l, v normalized, l
// and v pointing away.
#ifdef MATERIAL_LAYERS
#include "brdf_layers.glsl"
float g_ambient_NdotV = 1.0;  // n.v of the surface whose ambient term brdf_ambient computes
#endif

vec3 brdf_eval_base(BrdfInput m, vec3 n, vec3 l, vec3 v, float diffuse_weight) {
    float NdotL = dot(n, l);
    float NdotV = dot(n, v);
    if (NdotL <= 0.0 || NdotV <= 0.0) return vec3(0.0);
    vec3 h = normalize(l + v);
    float NdotH = saturate(dot(n, h));
    float VdotH = saturate(dot(v, h));
    float alpha = brdf_alpha(m.roughness);
#ifdef MATERIAL_LAYERS
    float spec = m.anisotropy > 0.0 ? anisotropic_specular(m, n, l, v, h, alpha)
                                    : D_GGX(NdotH, alpha) * V_SmithGGXCorrelated(NdotL, NdotV, alpha);
    vec3 Fd = F_Schlick(dielectric_f0(m), vec3(dielectric_f90(m)), VdotH);
    vec3 Fm = F_Schlick(m.base_color, vec3(1.0), VdotH);
    // The film's reflectance at the view's angle n.v, as the extension's reference does: one value
    // for every light direction, so the diffuse keeps exactly 1 - F of it and the layer cannot
    // create energy (at the microfacet's v.h the film's colour bands could, measured: +0.3 % blue
    // over white Lambert at 400 nm).
    if (m.iridescence > 0.0) {
        Fd = mix(Fd, iridescent_fresnel(m, NdotV, dielectric_f0(m)) * dielectric_f90(m), m.iridescence);
        Fm = mix(Fm, iridescent_fresnel(m, NdotV, m.base_color), m.iridescence);
    }
#else
    float spec = D_GGX(NdotH, alpha) * V_SmithGGXCorrelated(NdotL, NdotV, alpha);
    vec3 Fd = F_Schlick(dielectric_f0(m), vec3(dielectric_f90(m)), VdotH);
    vec3 Fm = F_Schlick(m.base_color, vec3(1.0), VdotH);
#endif
    vec3 diffuse = m.base_color * INV_PI * diffuse_weight;
    vec3 dielectric = (1.0 - Fd) * diffuse + Fd * spec;
    vec3 metal = Fm * spec;
    return mix(dielectric, metal, m.metallic);
}
vec3 brdf_eval_weighted(BrdfInput m, vec3 n, vec3 l, vec3 v, float diffuse_weight) {
#ifdef MATERIAL_LAYERS
    return brdf_layers_over(m, n, l, v, brdf_eval_base(m, n, l, v, diffuse_weight));
#else
    return brdf_eval_base(m, n, l, v, diffuse_weight);
#endif
}
vec3 brdf_eval(BrdfInput m, vec3 n, vec3 l, vec3 v) { return brdf_eval_weighted(m, n, l, v, 1.0); }

// The share of light the dielectric's diffuse lobe keeps after its Fresnel, as brdf_eval_base
// weights it (the tracer's BRDF): (1 / pi) times the integral of (1 - F(v.h)) cos over the
// hemisphere of l, = 1 - f0 - (f90 - f0) S(n.v) with S(mu) = (1 / pi) int (1 - v.h)^5 cos dl,
// which depends on n.v alone (h is the half vector of l and v at any roughness); S is fitted by
// 0.028 (1 - mu)^2.5 (within 7e-4 of a quadrature; S(0) = 0.028). The split sum's usual
// 1 - (f0 A + f90 B) keeps for the diffuse lobe the part of F that a rough specular lobe loses
// to masking: a few per cent more light at each bounce, which a bright closed room compounds
// (+8.5 % in a white box of albedo 0.8).
vec3 dielectric_diffuse_weight(BrdfInput m, float NdotV) {
    vec3 f0 = dielectric_f0(m);
    float f90 = dielectric_f90(m);
    vec3 w = vec3(1.0) - f0 - (f90 - f0) * (0.028 * pow(1.0 - clamp(NdotV, 0.0, 1.0), 2.5));
#ifdef MATERIAL_LAYERS
    if (m.iridescence > 0.0) w = mix(w, vec3(1.0) - iridescent_fresnel(m, NdotV, f0) * f90, m.iridescence);
#endif
    return w;
}

// Light reflected towards v from environment light (split sum, Karis 2013): `ab` the BRDF LUT's
// (A, B) at this roughness and NdotV, `irradiance` for the Lambert lobe, `specular_radiance`
// prefiltered along the reflection vector; a transmissive dielectric replaces `transmission` of
// its Lambert lobe by `transmitted_radiance` tinted by the base colour (KHR_materials_transmission).
vec3 brdf_ambient(BrdfInput m, float NdotV, vec2 ab, vec3 irradiance, vec3 specular_radiance, float transmission,
                  vec3 transmitted_radiance) {
    vec3 spec_dielectric = dielectric_f0(m) * ab.x + dielectric_f90(m) * ab.y;
    vec3 spec_metal = m.base_color * ab.x + ab.y;
#ifdef MATERIAL_LAYERS
    // A thin film: its reflectance at the view (g_ambient_NdotV) scales the lobe's albedo A + B.
    if (m.iridescence > 0.0) {
        spec_dielectric = mix(spec_dielectric, iridescent_fresnel(m, g_ambient_NdotV, dielectric_f0(m)) * dielectric_f90(m) * (ab.x + ab.y), m.iridescence);
        spec_metal = mix(spec_metal, iridescent_fresnel(m, g_ambient_NdotV, m.base_color) * (ab.x + ab.y), m.iridescence);
    }
#endif
    // The diffuse lobe keeps 1 - F averaged over its lights (dielectric_diffuse_weight). Light
    // refracted through the surface scatters off the same microfacets as the specular lobe, with
    // 1 - F(v.h) where the reflection has F(v.h) (the tracer's dielectric): of the lobe's single-
    // scattering albedo A + B (F = 1), the reflection takes f0 A + f90 B and the refraction the
    // rest, (1 - f0) A + (1 - f90) B. At a grazing view that is little, so reflected and
    // transmitted never add up to more than arrives, and a rough interface loses what its
    // microfacets shadow, as the tracer's single-scattering lobes do.
    vec3 diffuse = dielectric_diffuse_weight(m, NdotV) * m.base_color * INV_PI * irradiance;
    vec3 through = max(vec3(ab.x + ab.y) - spec_dielectric, vec3(0.0)) * m.base_color * transmitted_radiance;
    vec3 dielectric = mix(diffuse, through, transmission) + spec_dielectric * specular_radiance;
    vec3 metal = spec_metal * specular_radiance;
    return mix(dielectric, metal, m.metallic);
}
