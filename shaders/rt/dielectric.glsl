// Transmissive surfaces (KHR_materials_transmission) as the tracer's paths cross them, shared by
// path mode's camera paths and the GI probes' rays (engine/effects/gi/probe_trace.comp): one
// dielectric interface that reflects or refracts the path, smooth or rough, and the absorption
// inside a solid transmissive object (KHR_materials_volume). docs/raytracing.md, "Transmission".
#include "brdf_sampling.glsl"

// Below this alpha (brdf_alpha's own floor: a lobe narrower than a tenth of a degree) the interface
// is the exact smooth one, whose images the tests and goldens hold; above it the microfacet lobe.
const float DIELECTRIC_SMOOTH_ALPHA = 1e-3;

// Smith's masking term 1 / G1 = 1 + Lambda for GGX (Lambda of the height-correlated G2 below).
float ggx_one_plus_lambda(float cos_t, float alpha) { return 1.0 / smith_g1_ggx(max(cos_t, 1e-7), alpha); }

// The next direction of a path that meets the dielectric at s from direction v (towards the
// viewer), and the path's weight for it (the BSDF times the cosine over the sampling pdf).
// `below`: the direction leaves through the surface (offset the next ray along -ng). Returns false
// when the path ends here (a rough lobe's sample on the wrong side of the geometric surface).
//
// Smooth (alpha <= DIELECTRIC_SMOOTH_ALPHA): reflect about ng with probability F (exact Fresnel),
// refract otherwise; weight 1 (times the base colour when refracted). One random number, as before
// the rough lobe existed, so smooth images are unchanged sample for sample.
//
// Rough: Walter, Marschner, Li & Torrance 2007, "Microfacet Models for Refraction through Rough
// Surfaces" (EGSR), with GGX about the geometric normal. A microfacet normal h is drawn from the
// visible normals D_v(h) = G1(v) max(0, v.h) D(h) / (n.v) (Heitz 2018), then, as in their section
// 5.3, reflect about h with probability F(v.h) (exact Fresnel of that microfacet) or refract about
// it with 1 - F. With the BRDF f_r = F D G2 / (4 |n.v| |n.l|) and the BTDF of their eq. 21,
//     f_t = |v.h| |l.h| / (|n.v| |n.l|) * eta_t^2 (1 - F) D G2 / (eta_i (v.h) + eta_t (l.h))^2,
// and the pdfs F D_v(h) / (4 v.h) (reflection) and (1 - F) D_v(h) eta_t^2 |l.h| / (eta_i (v.h) +
// eta_t (l.h))^2 (refraction, the Jacobian of their eq. 17), F, D, the Jacobians and |n.l| cancel:
// the weight is G2 / G1(v) in both branches. G2 is the height-correlated Smith term on the
// reflected side, 1 / (1 + Lambda(v) + Lambda(l)) (the BRDF's V_SmithGGXCorrelated), and Walter's
// separable G1(v) G1(l) on the refracted side (the height-correlated form across an interface is
// a Beta function), so the weights are (1 + Lambda(v)) / (1 + Lambda(v) + Lambda(l)) and G1(l).
// Both are at most 1: the energy a single-scattering microfacet model loses (light that would
// scatter again among the microfacets) is missing, never added. The radiance scaling
// (eta_i / eta_t)^2 at a refraction is left out, as in the smooth branch: it cancels on every path
// that enters and leaves a closed object, and the camera and the lights are outside.
//
// Thin walls (material_thin): the wall stands for two parallel interfaces close together, so it
// scatters the transmitted light by the rough lobe without bending it on average. The transmitted
// direction is the microfacet reflection r = reflect(-v, h) mirrored through the geometric plane,
// r - 2 (n.r) n (the thin-walled BTDF of the glTF transmission extension): for h = n that is -v,
// the smooth thin wall's straight path, and the weight is the reflection's, G2 / G1(v), times the
// base colour. Fresnel as in the smooth thin wall: one interface entered, eta = 1 / ior.
bool dielectric_scatter(SurfaceHit s, BrdfInput m, vec3 v, inout Rng rng, out vec3 l, out vec3 weight, out bool below) {
    bool thin = material_thin(s.material);
    float eta = thin ? 1.0 : (s.front ? 1.0 / m.ior : m.ior);  // n_incident / n_transmitted
    float eta_fresnel = thin ? 1.0 / m.ior : eta;
    float alpha = brdf_alpha(m.roughness);
    weight = vec3(1.0);
    if (alpha <= DIELECTRIC_SMOOTH_ALPHA) {
        float F = fresnel_dielectric(dot(v, s.ng), eta_fresnel);
        below = rng_next(rng) >= F;
        if (!below) {
            l = reflect(-v, s.ng);
        } else {
            l = thin ? -v : refract(-v, s.ng, eta);
            weight = m.base_color;
        }
        return true;
    }
    vec3 n = s.ng, t, b;
    onb(n, t, b);
    vec3 v_local = vec3(dot(v, t), dot(v, b), dot(v, n));
    vec2 u = vec2(rng_next(rng), rng_next(rng));
    vec3 h_local = sample_ggx_vndf(v_local, alpha, u);
    vec3 h = normalize(h_local.x * t + h_local.y * b + h_local.z * n);
    float vh = dot(v, h);
    float F = fresnel_dielectric(vh, eta_fresnel);
    float lv = ggx_one_plus_lambda(v_local.z, alpha);  // 1 + Lambda(v)
    below = rng_next(rng) >= F;
    if (!below || thin) {
        vec3 r = reflect(-v, h);
        float nr = dot(n, r);
        if (nr <= 0.0) return false;  // reflected below the surface: lost (single scattering)
        l = below ? r - 2.0 * nr * n : r;
        weight = vec3(lv / (lv + ggx_one_plus_lambda(nr, alpha) - 1.0));
        if (below) weight *= m.base_color;
        return true;
    }
    l = refract(-v, h, eta);  // F < 1 here, so no total internal reflection about h
    float nl = -dot(n, l);
    if (nl <= 0.0) return false;  // refracted back above the surface: lost
    weight = m.base_color / ggx_one_plus_lambda(nl, alpha);  // G1(l)
    return true;
}

// KHR_materials_volume, Beer-Lambert: the fraction of light left after a segment of length d
// that ends on s. A segment that ends on a back face of a solid (not thin-walled) transmissive
// material ran inside its volume (the path entered it through a front face, or was reflected
// inside): transmittance attenuation_color^(d / attenuation_distance). Every other segment ran
// in air. The medium is known from where the segment ends, so a volume is assumed closed and not
// to overlap another (an opaque object inside glass: the segment to its front face is not
// attenuated).
vec3 volume_transmittance(SurfaceHit s, float d) {
    if (s.front) return vec3(1.0);
    MaterialData m = materials[s.material];
    if (m.transmission <= 0.0 || m.thickness <= 0.0 || m.attenuation_distance <= 0.0) return vec3(1.0);
    return pow(m.attenuation_color, vec3(d / m.attenuation_distance));
}
