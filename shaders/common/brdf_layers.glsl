// The layers of the glTF material extensions over the base BRDF of brdf.glsl, for lights (the
// tracer integrates exactly these) and for the rasterizer's environment term. Included by
// brdf.glsl when MATERIAL_LAYERS is defined (only programs of scenes whose materials use a layer
// pay for it). From the top: clearcoat, sheen, then the base, whose specular lobe may be
// anisotropic and whose Fresnel term may be a thin film's.
#include "sheen_albedo.glsl"

// ---- anisotropic GGX (KHR_materials_anisotropy) -------------------------------------------------
// alpha_t = mix(alpha, 1, strength^2) along the direction of anisotropy t, alpha_b = alpha across
// it; D and the height-correlated Smith V of the anisotropic GGX (Heitz 2014, eq. 85 and 99).
vec2 aniso_alphas(BrdfInput m, float alpha) { return vec2(mix(alpha, 1.0, m.anisotropy * m.anisotropy), alpha); }
void aniso_frame(BrdfInput m, vec3 n, out vec3 t, out vec3 b) {
    t = m.aniso_t - n * dot(n, m.aniso_t);
    float len = length(t);
    if (len < 1e-6) {
        vec3 o = abs(n.x) < 0.9 ? vec3(1.0, 0.0, 0.0) : vec3(0.0, 1.0, 0.0);
        t = normalize(o - n * dot(n, o));
    } else {
        t /= len;
    }
    b = cross(n, t);
}
float D_GGX_aniso(vec3 h_local, vec2 a) {
    vec3 s = vec3(h_local.x / a.x, h_local.y / a.y, h_local.z);
    float d = dot(s, s);
    return 1.0 / (PI * a.x * a.y * d * d);
}
float lambda_aniso(vec3 w_local, vec2 a) {
    return length(vec3(a.x * w_local.x, a.y * w_local.y, w_local.z));
}
float anisotropic_specular(BrdfInput m, vec3 n, vec3 l, vec3 v, vec3 h, float alpha) {
    vec3 t, b;
    aniso_frame(m, n, t, b);
    vec2 a = aniso_alphas(m, alpha);
    vec3 hl = vec3(dot(t, h), dot(b, h), dot(n, h));
    vec3 ll = vec3(dot(t, l), dot(b, l), dot(n, l));
    vec3 vl = vec3(dot(t, v), dot(b, v), dot(n, v));
    float denom = ll.z * lambda_aniso(vl, a) + vl.z * lambda_aniso(ll, a);
    return denom > 0.0 ? D_GGX_aniso(hl, a) * 0.5 / denom : 0.0;
}

// ---- thin-film iridescence (KHR_materials_iridescence) ------------------------------------------
// Belcour & Barla 2017, "A Practical Extension to Microfacet Theory for the Modeling of Varying
// Iridescence": the Airy sum of a film of index eta2 and thickness d over the base (its index
// recovered from F0), with the spectral integration done analytically by Gaussian fits of the
// CIE sensitivities (their supplemental's fit), converted from XYZ to linear Rec.709.
vec3 iridescence_sensitivity(float opd, vec3 shift) {
    float phase = 2.0 * PI * opd * 1.0e-9;
    const vec3 val = vec3(5.4856e-13, 4.4201e-13, 5.2481e-13);
    const vec3 pos = vec3(1.6810e+06, 1.7953e+06, 2.2084e+06);
    const vec3 var = vec3(4.3278e+09, 9.3046e+09, 6.6121e+09);
    vec3 xyz = val * sqrt(2.0 * PI * var) * cos(pos * phase + shift) * exp(-phase * phase * var);
    xyz.x += 9.7470e-14 * sqrt(2.0 * PI * 4.5282e+09) * cos(2.2399e+06 * phase + shift.x) * exp(-4.5282e+09 * phase * phase);
    xyz /= 1.0685e-7;
    const mat3 xyz_to_rec709 = mat3(3.2404542, -0.9692660, 0.0556434, -1.5371385, 1.8760108, -0.2040259,
                                    -0.4985314, 0.0415560, 1.0572252);
    return xyz_to_rec709 * xyz;
}
float ior_to_f0(float n_t, float n_i) {
    float r = (n_t - n_i) / (n_t + n_i);
    return r * r;
}
vec3 f0_to_ior(vec3 f0) {
    vec3 s = sqrt(clamp(f0, vec3(0.0), vec3(0.9999)));
    return (1.0 + s) / (1.0 - s);
}
// Reflectance at cos_i (outside index 1) of the film over a base of reflectance f0 at normal incidence.
vec3 iridescent_fresnel(BrdfInput m, float cos_i, vec3 f0) {
    float d = m.iridescence_thickness;
    // A film thinner than ~30 nm fades into the outside medium (no film: the base's own Fresnel).
    float eta2 = mix(1.0, m.iridescence_ior, smoothstep(0.0, 30.0, d));
    float sin2_t = (1.0 - cos_i * cos_i) / (eta2 * eta2);
    if (sin2_t >= 1.0) return vec3(1.0);
    float cos_t = sqrt(1.0 - sin2_t);
    // Air-film interface (Schlick at the incident angle).
    float R12 = ior_to_f0(eta2, 1.0);
    R12 = R12 + (1.0 - R12) * pow5(1.0 - cos_i);
    float T121 = 1.0 - R12;
    float phi12 = eta2 < 1.0 ? PI : 0.0;
    float phi21 = PI - phi12;
    // Film-base interface.
    vec3 base_ior = f0_to_ior(f0);
    vec3 R1 = vec3(ior_to_f0(base_ior.r, eta2), ior_to_f0(base_ior.g, eta2), ior_to_f0(base_ior.b, eta2));
    vec3 R23 = R1 + (1.0 - R1) * pow5(1.0 - cos_t);
    vec3 phi23 = vec3(base_ior.r < eta2 ? PI : 0.0, base_ior.g < eta2 ? PI : 0.0, base_ior.b < eta2 ? PI : 0.0);
    float opd = 2.0 * eta2 * d * cos_t;
    vec3 phi = vec3(phi21) + phi23;
    vec3 R123 = clamp(R12 * R23, 1e-5, 0.9999);
    vec3 r123 = sqrt(R123);
    vec3 Rs = T121 * T121 * R23 / (1.0 - R123);
    vec3 I = R12 + Rs;  // the sum's m = 0 term
    vec3 Cm = Rs - T121;
    for (int k = 1; k <= 2; ++k) {
        Cm *= r123;
        I += Cm * 2.0 * iridescence_sensitivity(float(k) * opd, float(k) * phi);
    }
    return clamp(I, vec3(0.0), vec3(1.0));
}

// ---- sheen (KHR_materials_sheen) ----------------------------------------------------------------
// Charlie distribution with its fitted height-correlated shadowing (Estevez & Kulla 2017). The
// fit lets the lobe's albedo E exceed 1 at grazing views of the smoothest sheens (up to 2.7 at
// roughness 0.07, cos 0); the lobe is divided by max(E(v), 1) there, so that no view reflects
// more than it receives. The layers below keep 1 - max(colour) min(E, 1) of their light, from the
// view and from the light (the extension's albedo scaling), so the stack stays within 1.
const float kSheenMinRoughness = 0.07;
float sheen_alpha(float r) { float c = max(r, kSheenMinRoughness); return c * c; }
float sheen_table_albedo(float cos_v, float r) {
    float x = clamp(cos_v, 0.0, 1.0) * float(SHEEN_ALBEDO_SIZE - 1);
    float y = clamp(r, 0.0, 1.0) * float(SHEEN_ALBEDO_SIZE - 1);
    int x0 = min(int(x), SHEEN_ALBEDO_SIZE - 2), y0 = min(int(y), SHEEN_ALBEDO_SIZE - 2);
    float fx = x - float(x0), fy = y - float(y0);
    int i = y0 * SHEEN_ALBEDO_SIZE + x0;
    float a = mix(kSheenAlbedo[i], kSheenAlbedo[i + 1], fx);
    float b = mix(kSheenAlbedo[i + SHEEN_ALBEDO_SIZE], kSheenAlbedo[i + SHEEN_ALBEDO_SIZE + 1], fx);
    return mix(a, b, fy);
}
// The albedo of the normalised lobe (colour 1): min(E, 1).
float sheen_albedo(float cos_v, float r) { return min(sheen_table_albedo(cos_v, r), 1.0); }
float charlie_fit(float x, float alpha) {
    float t = (1.0 - alpha) * (1.0 - alpha);
    float a = mix(21.5473, 25.3245, t), b = mix(3.82987, 3.32435, t), c = mix(0.19823, 0.16801, t);
    float d = mix(-1.97760, -1.27393, t), e = mix(-4.32054, -4.85967, t);
    return a / (1.0 + b * pow(max(x, 0.0), c)) + d * x + e;
}
float charlie_lambda(float cos_t, float alpha) {
    return cos_t < 0.5 ? exp(charlie_fit(cos_t, alpha)) : exp(2.0 * charlie_fit(0.5, alpha) - charlie_fit(1.0 - cos_t, alpha));
}
// The sheen lobe's value (without colour and cosine).
float sheen_lobe(BrdfInput m, float NdotL, float NdotV, float NdotH) {
    float alpha = sheen_alpha(m.sheen_roughness);
    float inv = 1.0 / alpha;
    float sin2 = max(1.0 - NdotH * NdotH, 0.0);
    float D = (2.0 + inv) * pow(sin2, 0.5 * inv) * (0.5 * INV_PI);
    float G = 1.0 / (1.0 + charlie_lambda(NdotV, alpha) + charlie_lambda(NdotL, alpha));
    return D * G / (4.0 * NdotL * NdotV) / max(sheen_table_albedo(NdotV, m.sheen_roughness), 1.0);
}

// ---- clearcoat (KHR_materials_clearcoat) --------------------------------------------------------
// A GGX lobe about the coat normal (no Fresnel inside), over the rest weighted by the coat's
// Fresnel at the view, Schlick with F0 0.04 (ior 1.5): f = (1 - c Fc) f_below + c Fc f_coat. A
// smooth coat over a white Lambert base reflects exactly 1 (Fc + (1 - Fc)).
float coat_fresnel(BrdfInput m, vec3 v) {
    float c = saturate(abs(dot(m.coat_n, v)));
    return m.clearcoat * (0.04 + 0.96 * pow5(1.0 - c));
}
float coat_lobe(BrdfInput m, vec3 l, vec3 v) {
    float NdotL = dot(m.coat_n, l), NdotV = dot(m.coat_n, v);
    if (NdotL <= 0.0 || NdotV <= 0.0) return 0.0;
    float alpha = brdf_alpha(m.clearcoat_roughness);
    float NdotH = saturate(dot(m.coat_n, normalize(l + v)));
    return D_GGX(NdotH, alpha) * V_SmithGGXCorrelated(NdotL, NdotV, alpha);
}

// The whole stack for light from l, given the base BRDF's value `base`.
vec3 brdf_layers_over(BrdfInput m, vec3 n, vec3 l, vec3 v, vec3 base) {
    float sheen_max = max(m.sheen_color.r, max(m.sheen_color.g, m.sheen_color.b));
    vec3 f = base;
    if (sheen_max > 0.0) {
        float NdotL = dot(n, l), NdotV = dot(n, v);
        if (NdotL > 0.0 && NdotV > 0.0) {
            float scale = min(1.0 - sheen_max * sheen_albedo(NdotV, m.sheen_roughness),
                              1.0 - sheen_max * sheen_albedo(NdotL, m.sheen_roughness));
            f = f * scale + m.sheen_color * sheen_lobe(m, NdotL, NdotV, saturate(dot(n, normalize(l + v))));
        }
    }
    if (m.clearcoat > 0.0) {
        float fc = coat_fresnel(m, v);
        f = f * (1.0 - fc) + vec3(fc * coat_lobe(m, l, v));
    }
    return f;
}

// The stack for environment light (the rasterizer's split sum): `below` the base's ambient term,
// `irradiance` for the sheen (a near-diffuse lobe: exact for a uniform environment), the coat
// lit by `coat_radiance` (prefiltered along the coat's reflection) with `coat_ab` the split-sum
// table at the coat's roughness.
vec3 layers_ambient(BrdfInput m, vec3 n, vec3 v, vec3 below, vec3 irradiance, vec3 coat_radiance, vec2 coat_ab) {
    float sheen_max = max(m.sheen_color.r, max(m.sheen_color.g, m.sheen_color.b));
    vec3 c = below;
    if (sheen_max > 0.0) {
        float e = sheen_albedo(saturate(dot(n, v)), m.sheen_roughness);
        c = c * (1.0 - sheen_max * e) + m.sheen_color * e * irradiance * INV_PI;
    }
    if (m.clearcoat > 0.0) {
        float fc = coat_fresnel(m, v);
        c = c * (1.0 - fc) + fc * (coat_ab.x + coat_ab.y) * coat_radiance;
    }
    return c;
}
