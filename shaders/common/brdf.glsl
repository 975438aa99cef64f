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
};

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

// BRDF value f(l, v) (without the cosine). n, l, v normalized, l and v pointing away.
vec3 brdf_eval(BrdfInput m, vec3 n, vec3 l, vec3 v) {
    float NdotL = dot(n, l);
    float NdotV = dot(n, v);
    if (NdotL <= 0.0 || NdotV <= 0.0) return vec3(0.0);
    vec3 h = normalize(l + v);
    float NdotH = saturate(dot(n, h));
    float VdotH = saturate(dot(v, h));
    float alpha = brdf_alpha(m.roughness);
    float spec = D_GGX(NdotH, alpha) * V_SmithGGXCorrelated(NdotL, NdotV, alpha);
    vec3 diffuse = m.base_color * INV_PI;
    vec3 Fd = F_Schlick(dielectric_f0(m), vec3(dielectric_f90(m)), VdotH);
    vec3 dielectric = (1.0 - Fd) * diffuse + Fd * spec;
    vec3 metal = F_Schlick(m.base_color, vec3(1.0), VdotH) * spec;
    return mix(dielectric, metal, m.metallic);
}

// Directional albedo of the specular lobe, split into F0 and F90 scales: Karis' analytic fit to
// the split-sum LUT ("Physically Based Shading on Mobile", 2014). Used for constant-environment
// ambient until the prefiltered LUT (reflections issue) replaces it.
vec2 env_brdf_approx(float roughness, float NdotV) {
    const vec4 c0 = vec4(-1.0, -0.0275, -0.572, 0.022);
    const vec4 c1 = vec4(1.0, 0.0425, 1.04, -0.04);
    vec4 r = roughness * c0 + c1;
    float a004 = min(r.x * r.x, exp2(-9.28 * NdotV)) * r.x + r.y;
    return vec2(-1.04, 1.04) * a004 + r.zw;
}

// Light reflected towards v from incident radiance that is `irradiance_diffuse / PI` (diffuse
// lobe) and `radiance_specular` (prefiltered along the reflection vector).
vec3 brdf_ambient(BrdfInput m, vec3 n, vec3 v, vec3 irradiance, vec3 specular_radiance) {
    float NdotV = saturate(dot(n, v));
    vec2 ab = env_brdf_approx(m.roughness, NdotV);
    vec3 spec_dielectric = dielectric_f0(m) * ab.x + dielectric_f90(m) * ab.y;
    vec3 spec_metal = m.base_color * ab.x + ab.y;
    vec3 diffuse = m.base_color * INV_PI * irradiance;
    vec3 dielectric = (1.0 - spec_dielectric) * diffuse + spec_dielectric * specular_radiance;
    vec3 metal = spec_metal * specular_radiance;
    return mix(dielectric, metal, m.metallic);
}
