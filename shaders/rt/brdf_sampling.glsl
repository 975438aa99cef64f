// Importance sampling of the BRDF for the tracer's estimators (path mode's bounces and the MIS
// weights of direct light), and the folding of the BRDF into the geometric hemisphere that every
// mode's shading uses.
#include "materials.glsl"

// ---- BRDF sampling (lobe mixture: GGX visible normals + cosine) -------------------------------

float specular_lobe_probability(BrdfInput m) {
    if (m.metallic <= 0.0 && m.specular_factor <= 0.0) return 0.0;
#ifdef MATERIAL_LAYERS
    // A sheen needs the cosine lobe, also on metal.
    if (max(m.sheen_color.r, max(m.sheen_color.g, m.sheen_color.b)) > 0.0) return mix(0.25, 0.75, m.metallic);
#endif
    return mix(0.25, 1.0, m.metallic);
}

float brdf_pdf_base(BrdfInput m, vec3 n, vec3 v, vec3 l) {
    float NdotL = dot(n, l), NdotV = dot(n, v);
    if (NdotL <= 0.0 || NdotV <= 0.0) return 0.0;
    float ps = specular_lobe_probability(m);
    vec3 h = normalize(v + l);
    float spec = 0.0;
#ifdef MATERIAL_LAYERS
    if (ps > 0.0 && m.anisotropy > 0.0) {
        // Visible-normal pdf of the anisotropic lobe: G1(v) D(h) / (4 n.v).
        vec3 t, b;
        aniso_frame(m, n, t, b);
        vec2 a = aniso_alphas(m, brdf_alpha(m.roughness));
        vec3 vl = vec3(dot(t, v), dot(b, v), NdotV);
        float g1 = 2.0 * NdotV / (NdotV + lambda_aniso(vl, a));
        spec = g1 * D_GGX_aniso(vec3(dot(t, h), dot(b, h), dot(n, h)), a) / (4.0 * NdotV);
    } else
#endif
    spec = ps > 0.0 ? pdf_ggx_vndf_reflection(NdotV, saturate(dot(n, h)), brdf_alpha(m.roughness)) : 0.0;
    return ps * spec + (1.0 - ps) * pdf_cosine_hemisphere(NdotL);
}

vec3 sample_brdf_base(BrdfInput m, vec3 n, vec3 v, inout Rng rng) {
    float ps = specular_lobe_probability(m);
    vec2 u = vec2(rng_next(rng), rng_next(rng));
    if (rng_next(rng) < ps) {
        vec3 t, b;
#ifdef MATERIAL_LAYERS
        vec2 a = vec2(brdf_alpha(m.roughness));
        if (m.anisotropy > 0.0) {
            aniso_frame(m, n, t, b);
            a = aniso_alphas(m, a.x);
        } else {
            onb(n, t, b);
        }
        vec3 v_local = vec3(dot(v, t), dot(v, b), dot(v, n));
        vec3 h_local = sample_ggx_vndf_aniso(v_local, a, u);
#else
        onb(n, t, b);
        vec3 v_local = vec3(dot(v, t), dot(v, b), dot(v, n));
        vec3 h_local = sample_ggx_vndf(v_local, brdf_alpha(m.roughness), u);
#endif
        vec3 h = h_local.x * t + h_local.y * b + h_local.z * n;
        return reflect(-v, h);
    }
    return to_world(sample_cosine_hemisphere(u), n);
}

#ifdef MATERIAL_LAYERS
// The clearcoat's own lobe (GGX visible normals about the coat normal), chosen with probability
// half the coat's weight.
float coat_lobe_probability(BrdfInput m) { return 0.5 * m.clearcoat; }
float brdf_pdf(BrdfInput m, vec3 n, vec3 v, vec3 l) {
    float pc = coat_lobe_probability(m);
    float base = brdf_pdf_base(m, n, v, l);
    if (pc <= 0.0) return base;
    float NcL = dot(m.coat_n, l), NcV = dot(m.coat_n, v);
    float coat = NcL > 0.0 && NcV > 0.0
        ? pdf_ggx_vndf_reflection(NcV, saturate(dot(m.coat_n, normalize(v + l))), brdf_alpha(m.clearcoat_roughness)) : 0.0;
    return pc * coat + (1.0 - pc) * base;
}
vec3 sample_brdf(BrdfInput m, vec3 n, vec3 v, inout Rng rng) {
    float pc = coat_lobe_probability(m);
    if (pc > 0.0 && rng_next(rng) < pc) {
        vec2 u = vec2(rng_next(rng), rng_next(rng));
        vec3 t, b;
        onb(m.coat_n, t, b);
        vec3 v_local = vec3(dot(v, t), dot(v, b), dot(v, m.coat_n));
        if (v_local.z <= 0.0) return -m.coat_n;  // the coat faces away: no sample (pdf 0 there)
        vec3 h_local = sample_ggx_vndf(v_local, brdf_alpha(m.clearcoat_roughness), u);
        return reflect(-v, h_local.x * t + h_local.y * b + h_local.z * m.coat_n);
    }
    return sample_brdf_base(m, n, v, rng);
}
#else
float brdf_pdf(BrdfInput m, vec3 n, vec3 v, vec3 l) { return brdf_pdf_base(m, n, v, l); }
vec3 sample_brdf(BrdfInput m, vec3 n, vec3 v, inout Rng rng) { return sample_brdf_base(m, n, v, rng); }
#endif

float power_heuristic(float a, float b) {
    float a2 = a * a, b2 = b * b;
    return a2 + b2 > 0.0 ? a2 / (a2 + b2) : 0.0;
}

// ---- shading normals: the BRDF folded into the geometric hemisphere ---------------------------
// A shading normal ns (interpolated, or from a normal map) differs from the geometric normal ng,
// so the BRDF evaluated about ns sends part of its light to directions below the geometric
// surface: a mirror reflection about ns can point into the object. Tracing those rays, or
// dropping them, gave the black rings on normal-mapped metal. Here the BRDF the tracer
// integrates is folded at the geometric tangent plane: for l above it,
//     f_fold(v, l) cos = f(v, l) (ns.l) + f(v, M l) (ns.M l),   M l = l - 2 (ng.l) ng,
// i.e. the light the ns-BRDF would reflect below the surface leaves at its mirror image about
// the geometric plane instead (the "flip" convention for shading normals; the microfacet model
// of Schuessler et al. 2017, "Microfacet-based Normal Mapping for Robust Monte Carlo Path
// Tracing", is the energy-exact alternative, which the rasterizer could not match). Its albedo is
// the ns-BRDF's own, E(ns.v), which is what the raster's split-sum term computes with the same
// bent normal, so a white furnace gives the same answer on both. Sampling draws l from the ns
// lobes and reflects it at the geometric plane if it lies below; that direction's density is
// pdf(l) + pdf(M l), which is also the pdf MIS uses, so next-event estimation (which evaluates
// the same folded BRDF) and BRDF sampling stay consistent. Rays leave offset along ng.
vec3 fold_above(vec3 l, vec3 ng) {
    float d = dot(l, ng);
    return d < 0.0 ? l - 2.0 * d * ng : l;
}
// f_fold * cosine for a direction l (0 below the geometric surface).
vec3 brdf_cos_folded(BrdfInput m, SurfaceHit s, vec3 l, vec3 v) {
    float gl = dot(s.ng, l);
    if (gl <= 0.0) return vec3(0.0);
    vec3 lm = l - 2.0 * gl * s.ng;
    float c = dot(s.ns, l), cm = dot(s.ns, lm);
    vec3 f = c > 0.0 ? brdf_eval(m, s.ns, l, v) * c : vec3(0.0);
    if (cm > 0.0) f += brdf_eval(m, s.ns, lm, v) * cm;
    return f;
}
// Solid-angle pdf of sample_brdf_folded drawing l.
float brdf_pdf_folded(BrdfInput m, SurfaceHit s, vec3 v, vec3 l) {
    float gl = dot(s.ng, l);
    if (gl <= 0.0) return 0.0;
    return brdf_pdf(m, s.ns, v, l) + brdf_pdf(m, s.ns, v, l - 2.0 * gl * s.ng);
}
// A direction from the ns lobes, reflected into the geometric hemisphere; false if the lobe's
// sample lies below the shading surface (the single-scattering loss, as in the raster's E(n.v)).
bool sample_brdf_folded(BrdfInput m, SurfaceHit s, vec3 v, inout Rng rng, out vec3 l) {
    l = sample_brdf(m, s.ns, v, rng);
    if (dot(s.ns, l) <= 0.0) return false;
    l = fold_above(l, s.ng);
    return dot(s.ng, l) > 0.0;
}
