#version 450 core
// The compute-shader ray tracer: one sample per pixel per dispatch, accumulated in `accum`.
// Modes (one is defined by the host): MODE_AO, MODE_PATH (MODE_DIRECT is MODE_PATH with one
// bounce), MODE_INDIRECT, MODE_WHITTED. Scene features compiled in only when the scene has them:
// HAS_EMITTERS (emissive triangles), HAS_TRANSMISSION (KHR_materials_transmission), HAS_BLEND
// (alphaMode BLEND: layers composited along camera rays), HAS_MASK (alphaMode MASK: every ray
// tests the cutoff at candidate hits).
#if !defined(MODE_AO) && !defined(MODE_PATH) && !defined(MODE_INDIRECT) && !defined(MODE_WHITTED) && \
    !defined(MODE_PRIMARY) && !defined(MODE_VISIBILITY) && !defined(MODE_BOUNCE)
#define MODE_PATH  // the default when validated without defines
#endif
#include "../common/scene_data.glsl"
#include "../common/brdf.glsl"
#include "../common/sampling.glsl"
layout(std430, binding = 10) buffer Diagnostics {
    uint nonfinite_samples;
    uint traversal_nodes;      // RT_STATS only: BVH nodes visited, all rays
    uint traversal_primitives; // RT_STATS only: primitives intersected, all rays
    uint traversal_rays;       // RT_STATS only
};
layout(local_size_x = 8, local_size_y = 8) in;  // before scene.glsl: its traversal stacks are sized by it
#include "scene.glsl"

layout(std430, binding = 9) buffer Accum { vec4 accum[]; };  // rgb sum, w sample count
layout(binding = 5) uniform sampler2D t_environment;

// ---- materials -------------------------------------------------------------------------------

vec3 srgb_to_linear(vec3 c) {
    return mix(c / 12.92, pow((c + 0.055) / 1.055, vec3(2.4)), step(vec3(0.04045), c));
}

// The material at a hit, with its textures (base colour, metallic-roughness), as the forward pass
// reads them. Normal and occlusion maps are not used here: occlusion is what the tracer computes.
BrdfInput brdf_input(SurfaceHit s) {
    int mi = s.material;
    MaterialData m = materials[mi];
    BrdfInput b;
    b.base_color = m.base_color.rgb;
    b.metallic = saturate(m.emission_metallic.a);
    b.roughness = saturate(m.params.x);
    if (m.texcoord.x >= 0)
        b.base_color *= material_texture(m, 0, m.images.x, m.texcoord.x, s.uv0, s.uv1).rgb;
    if (m.texcoord.y >= 0) {
        vec4 mr = material_texture(m, 1, m.images.y, m.texcoord.y, s.uv0, s.uv1);
        b.roughness *= mr.g;
        b.metallic *= mr.b;
    }
    b.ior = m.params2.x;
    b.specular_factor = m.specular.a;
    b.specular_color = m.specular.rgb;
    return b;
}
vec3 surface_emission(SurfaceHit s) {
    MaterialData m = materials[s.material];
    vec3 e = m.emission_metallic.rgb;
    if (m.texcoord2.x >= 0)
        e *= material_texture(m, 4, m.images2.x, m.texcoord2.x, s.uv0, s.uv1).rgb;
    return e;
}
bool material_double_sided(int mi) { return materials[mi].params.w > 0.5; }

// alphaMode BLEND: the coverage the rasterizer blends with (SRC_ALPHA, ONE_MINUS_SRC_ALPHA); 1 for
// every other mode. Camera paths composite blended layers with it, in depth order, which is the
// exact answer sorted blending and depth peeling approximate. Shadow, AO and bounce rays treat
// blended surfaces as opaque, as the shadow maps do.
float blend_alpha(SurfaceHit s) {
    MaterialData m = materials[s.material];
    if (int(m.params.z) != 2) return 1.0;
    float a = m.base_color.a;
    if (m.texcoord.x >= 0) a *= material_texture(m, 0, m.images.x, m.texcoord.x, s.uv0, s.uv1).a;
    return saturate(a);
}
float material_transmission(int mi) { return materials[mi].params2.y; }
// KHR_materials_volume: thickness 0 is a thin wall (light passes without bending).
bool material_thin(int mi) { return materials[mi].volume.x <= 0.0; }

// Light leaving a surface towards the viewer by emission: front side, or both if double-sided.
vec3 emitted(SurfaceHit s) {
    return (s.front || material_double_sided(s.material)) ? surface_emission(s) : vec3(0.0);
}

vec3 environment(vec3 dir) {
    if (rt.env_radiance.w < 0.5) return rt.env_radiance.rgb;
    return rt.env_radiance.rgb * textureLod(t_environment, direction_to_equirect(normalize(dir)), 0.0).rgb;
}

#ifdef HAS_ENV_MAP_SAMPLING
// ---- environment map importance sampling -------------------------------------------------------
// env_dist: texel probabilities, row-conditional CDFs, marginal CDF (engine/rt/ray_tracer.hpp).
layout(std430, binding = 12) readonly buffer EnvDistribution { float env_dist[]; };

// Solid-angle pdf of drawing `dir` from the environment distribution.
float env_pdf(vec3 dir) {
    int w = rt.counts2.y, h = rt.counts2.z;
    vec2 uv = direction_to_equirect(normalize(dir));
    int x = clamp(int(uv.x * float(w)), 0, w - 1);
    int y = clamp(int(uv.y * float(h)), 0, h - 1);
    float sin_theta = sin(PI * (float(y) + 0.5) / float(h));
    if (sin_theta <= 0.0) return 0.0;
    return env_dist[y * w + x] * float(w * h) / (2.0 * PI * PI * sin_theta);
}

vec3 sample_env(inout Rng rng, out float pdf) {
    int w = rt.counts2.y, h = rt.counts2.z;
    int n = w * h;
    float u = rng_next(rng);
    int lo = 0, hi = h - 1;
    while (lo < hi) {
        int mid = (lo + hi) / 2;
        if (env_dist[2 * n + mid] < u) lo = mid + 1; else hi = mid;
    }
    int y = lo;
    float u2 = rng_next(rng);
    lo = 0;
    hi = w - 1;
    while (lo < hi) {
        int mid = (lo + hi) / 2;
        if (env_dist[n + y * w + mid] < u2) lo = mid + 1; else hi = mid;
    }
    int x = lo;
    // Uniform within the texel; the pdf uses the texel-centre sin(theta), as env_pdf does.
    float phi = ((float(x) + rng_next(rng)) / float(w) - 0.5) * 2.0 * PI;
    float theta = (float(y) + rng_next(rng)) / float(h) * PI;
    vec3 dir = vec3(sin(theta) * sin(phi), cos(theta), -sin(theta) * cos(phi));
    float sin_c = sin(PI * (float(y) + 0.5) / float(h));
    pdf = sin_c > 0.0 ? env_dist[y * w + x] * float(n) / (2.0 * PI * PI * sin_c) : 0.0;
    return dir;
}
#endif

// ---- BRDF sampling (lobe mixture: GGX visible normals + cosine) -------------------------------

float specular_lobe_probability(BrdfInput m) {
    if (m.metallic <= 0.0 && m.specular_factor <= 0.0) return 0.0;
    return mix(0.25, 1.0, m.metallic);
}

float brdf_pdf(BrdfInput m, vec3 n, vec3 v, vec3 l) {
    float NdotL = dot(n, l), NdotV = dot(n, v);
    if (NdotL <= 0.0 || NdotV <= 0.0) return 0.0;
    float ps = specular_lobe_probability(m);
    vec3 h = normalize(v + l);
    float spec = ps > 0.0 ? pdf_ggx_vndf_reflection(NdotV, saturate(dot(n, h)), brdf_alpha(m.roughness)) : 0.0;
    return ps * spec + (1.0 - ps) * pdf_cosine_hemisphere(NdotL);
}

vec3 sample_brdf(BrdfInput m, vec3 n, vec3 v, inout Rng rng) {
    float ps = specular_lobe_probability(m);
    vec2 u = vec2(rng_next(rng), rng_next(rng));
    if (rng_next(rng) < ps) {
        vec3 t, b;
        onb(n, t, b);
        vec3 v_local = vec3(dot(v, t), dot(v, b), dot(v, n));
        vec3 h_local = sample_ggx_vndf(v_local, brdf_alpha(m.roughness), u);
        vec3 h = h_local.x * t + h_local.y * b + h_local.z * n;
        return reflect(-v, h);
    }
    return to_world(sample_cosine_hemisphere(u), n);
}

float power_heuristic(float a, float b) {
    float a2 = a * a, b2 = b * b;
    return a2 + b2 > 0.0 ? a2 / (a2 + b2) : 0.0;
}

// ---- shading normals: the BRDF folded into the geometric hemisphere ---------------------------
// A shading normal ns (interpolated, or from a normal map) differs from the geometric normal ng,
// so the BRDF evaluated about ns sends part of its light to directions below the geometric
// surface: a mirror reflection about ns can point into the object. Tracing those rays, or
// dropping them, gave the black rings on normal-mapped metal (issue 17). Here the BRDF the tracer
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

// ---- direct light ------------------------------------------------------------------------------

Ray make_ray(vec3 origin, vec3 dir) {
    Ray r;
    r.origin = origin;
    r.dir = dir;
    return r;
}

// What fraction of light gets through along a shadow ray. Whitted's transparent shadows: each
// crossing of a transmissive surface passes (1 - F) * transmission * base colour along a straight
// line (exact for IOR 1; refraction's focusing is what path mode is for). Elsewhere, and for
// every opaque surface, it is plain visibility.
vec3 shadow_visibility(Ray ray, float tmax) {
#if defined(MODE_WHITTED) && defined(HAS_TRANSMISSION)
    vec3 T = vec3(1.0);
    for (int crossing = 0; crossing < 16; ++crossing) {
        Hit h = trace_closest(ray, tmax);
        if (h.prim < 0) return T;
        SurfaceHit s = surface_at(ray, h);
        float transmission = materials[s.material].params2.y;
        if (transmission <= 0.0) return vec3(0.0);
        BrdfInput m = brdf_input(s);
        bool thin = materials[s.material].volume.x <= 0.0;
        float eta = thin ? 1.0 / m.ior : (s.front ? 1.0 / m.ior : m.ior);
        float F = fresnel_dielectric(abs(dot(normalize(ray.dir), s.ng)), eta);
        T *= (1.0 - F) * transmission * m.base_color;
        if (max(T.r, max(T.g, T.b)) <= 0.0) return vec3(0.0);
        ray.origin = offset_ray(s.p, -s.ng, rt.fparams2.x);
        tmax -= h.t;
    }
    return vec3(0.0);
#else
    return trace_any(ray, tmax) ? vec3(0.0) : vec3(1.0);
#endif
}

vec3 direct_punctual(SurfaceHit s, BrdfInput m, vec3 v) {
    vec3 sum = vec3(0.0);
    for (int i = 0; i < rt.counts.w; ++i) {
        vec3 l, E;
        float dist;
        light_incidence(lights[i], s.p, l, E, dist);
        if (max(E.r, max(E.g, E.b)) <= 0.0) continue;
        vec3 fc = brdf_cos_folded(m, s, l, v);
        if (max(fc.r, max(fc.g, fc.b)) <= 0.0) continue;
        vec3 visible = shadow_visibility(make_ray(offset_ray(s.p, s.ng, rt.fparams2.x), l), dist);
        sum += fc * E * visible;
    }
    return sum;
}

#ifdef HAS_EMITTERS
// 1 - cos of the half-angle a sphere of radius r subtends at distance^2 d2 (> r^2), without the
// cancellation of 1 - sqrt(1 - r^2/d2) for small or distant spheres.
float sphere_cone_one_minus_cos(float r, float d2) {
    float sin2 = r * r / d2;
    return sin2 / (1.0 + sqrt(max(1.0 - sin2, 0.0)));
}

// An emissive sphere: a direction uniformly in the cone it subtends (solid-angle pdf
// 1 / (2 pi (1 - cos_max))), the point where it meets the sphere, and MIS with the BRDF. From
// inside the sphere there is no cone: BRDF rays alone see its emission (emitter_pdf is 0 there).
vec3 direct_sphere(SurfaceHit s, BrdfInput m, vec3 v, inout Rng rng, bool use_mis, Emitter e) {
    RtSphere sp = spheres[int(e.triangle) - rt.counts.x];
    vec3 c = sp.center_radius.xyz;
    float r = sp.center_radius.w;
    vec3 dc = c - s.p;
    float d2 = dot(dc, dc);
    float u1 = rng_next(rng), u2 = rng_next(rng);
    if (d2 <= r * r) return vec3(0.0);
    float dist = sqrt(d2);
    float omc = sphere_cone_one_minus_cos(r, d2);
    float one_minus_cos_t = u1 * omc;
    float cos_t = 1.0 - one_minus_cos_t;
    float sin_t = sqrt(max(one_minus_cos_t * (2.0 - one_minus_cos_t), 0.0));
    float phi = 2.0 * PI * u2;
    vec3 l = to_world(vec3(cos(phi) * sin_t, sin(phi) * sin_t, cos_t), dc / dist);
    vec3 fc = brdf_cos_folded(m, s, l, v);
    if (max(fc.r, max(fc.g, fc.b)) <= 0.0) return vec3(0.0);
    // Nearest intersection along l (the tangent point if rounding puts l just outside).
    float along = dist * cos_t;
    float t = along - sqrt(max(r * r - (d2 - along * along), 0.0));
    vec3 q = s.p + l * t;
    vec3 nl = normalize(q - c);
    int mat = sp.material_node.x;
    vec3 Le = materials[mat].emission_metallic.rgb;
    float pdf = e.pdf / (2.0 * PI * omc);
    vec3 origin = offset_ray(s.p, s.ng, rt.fparams2.x);
    vec3 target = offset_ray(q, nl, rt.fparams2.x);
    vec3 visible = shadow_visibility(make_ray(origin, target - origin), 1.0);
    float w = use_mis ? power_heuristic(pdf, brdf_pdf_folded(m, s, v, l)) : 1.0;
    return fc * Le * w * visible / pdf;
}

// One emitter chosen by power: an emissive triangle (one point on it uniformly by area) or an
// emissive sphere (direct_sphere); MIS with the BRDF.
vec3 direct_emitters(SurfaceHit s, BrdfInput m, vec3 v, inout Rng rng, bool use_mis) {
    float u = rng_next(rng);
    int lo = 0, hi = rt.counts.z - 1;
    while (lo < hi) {
        int mid = (lo + hi) / 2;
        if (emitters[mid].cdf < u) lo = mid + 1; else hi = mid;
    }
    Emitter e = emitters[lo];
    if (int(e.triangle) >= rt.counts.x) return direct_sphere(s, m, v, rng, use_mis, e);
    RtTriangle tri = load_triangle(int(e.triangle));
    float su = sqrt(rng_next(rng));
    float u2 = rng_next(rng);
    vec3 q = (1.0 - su) * tri.p0.xyz + su * (1.0 - u2) * tri.p1.xyz + su * u2 * tri.p2.xyz;
    vec3 nl = normalize(cross(tri.p1.xyz - tri.p0.xyz, tri.p2.xyz - tri.p0.xyz));
    int mat = floatBitsToInt(tri.p0.w);
    // The emission at the sampled point, with the emissive texture, as a BRDF ray would see it
    // (the emitter was chosen by its untextured power: still unbiased where the texture is > 0).
    vec3 Le = materials[mat].emission_metallic.rgb;
    if (materials[mat].texcoord2.x >= 0) {
        vec2 b = vec2(su * (1.0 - u2), su * u2);
        float w0 = 1.0 - b.x - b.y;
        vec2 uv0 = tri.uv_a.xy * w0 + tri.uv_a.zw * b.x + tri.uv_b.xy * b.y;
        vec2 uv1 = tri.uv_b.zw * w0 + tri.uv_c.xy * b.x + tri.uv_c.zw * b.y;
        MaterialData me = materials[mat];
        Le *= material_texture(me, 4, me.images2.x, me.texcoord2.x, uv0, uv1).rgb;
    }
    vec3 d = q - s.p;
    float dist2 = dot(d, d);
    if (dist2 <= 0.0) return vec3(0.0);
    vec3 l = d * inversesqrt(dist2);
    float cos_l = dot(nl, -l);
    if (material_double_sided(mat)) cos_l = abs(cos_l);
    if (cos_l <= 0.0) return vec3(0.0);
    vec3 fc = brdf_cos_folded(m, s, l, v);
    if (max(fc.r, max(fc.g, fc.b)) <= 0.0) return vec3(0.0);
    float pdf = e.pdf / e.area * dist2 / cos_l;  // solid angle
    vec3 origin = offset_ray(s.p, s.ng, rt.fparams2.x);
    vec3 target = offset_ray(q, dot(nl, -l) > 0.0 ? nl : -nl, rt.fparams2.x);
    vec3 visible = shadow_visibility(make_ray(origin, target - origin), 1.0);
    float w = use_mis ? power_heuristic(pdf, brdf_pdf_folded(m, s, v, l)) : 1.0;
    return fc * Le * w * visible / pdf;
}

// Solid-angle pdf with which direct_emitters would have chosen the point the BRDF ray hit.
float emitter_pdf(Ray ray, Hit hit, SurfaceHit s) {
    if (hit.prim >= rt.counts.x) {
        RtSphere sp = spheres[hit.prim - rt.counts.x];
        float select = intBitsToFloat(sp.material_node.z);
        vec3 dc = sp.center_radius.xyz - ray.origin;
        float d2 = dot(dc, dc), r = sp.center_radius.w;
        if (select <= 0.0 || d2 <= r * r) return 0.0;
        return select / (2.0 * PI * sphere_cone_one_minus_cos(r, d2));
    }
    RtTriangle tri = load_triangle(hit.prim);
    float select_pdf = tri.n0.w;
    if (select_pdf <= 0.0) return 0.0;
    vec3 c = cross(tri.p1.xyz - tri.p0.xyz, tri.p2.xyz - tri.p0.xyz);
    float area = 0.5 * length(c);
    float dist = hit.t * length(ray.dir);
    float cos_l = abs(dot(normalize(c), normalize(ray.dir)));
    return cos_l > 0.0 ? select_pdf / area * dist * dist / cos_l : 0.0;
}
#endif

// ---- camera ------------------------------------------------------------------------------------

Ray camera_ray(ivec2 pixel, inout Rng rng) {
    vec2 jitter = rt.params.y != 0 ? vec2(rng_next(rng), rng_next(rng)) : vec2(0.5);
    vec2 ndc = vec2((float(pixel.x) + jitter.x) / float(rt.image.x) * 2.0 - 1.0,
                    1.0 - (float(pixel.y) + jitter.y) / float(rt.image.y) * 2.0);
    vec4 far_point = rt.inv_view_proj * vec4(ndc, 0.5, 1.0);
    vec4 near_point = rt.inv_view_proj * vec4(ndc, 1.0, 1.0);
    vec3 a = near_point.xyz / near_point.w;
    vec3 b = far_point.xyz / far_point.w;
    // Perspective: rays from the camera position; orthographic: from the near plane. The points
    // are relative to the camera, so precision does not depend on where the camera is.
    Ray r;
    r.origin = rt.camera_pos.xyz + a;
    r.dir = normalize(b - a);
    return r;
}

// ---- the modes ---------------------------------------------------------------------------------

#ifdef MODE_PRIMARY
// Camera rays only: the shading normal (0.5 + 0.5 n), black on a miss. For ray-rate benchmarks
// and as a debug view of what the tracer sees.
vec3 radiance(Ray ray, inout Rng rng) {
    Hit hit = trace_closest(ray, 3.0e38);
    if (hit.prim < 0) return vec3(0.0);
    return 0.5 + 0.5 * surface_at(ray, hit).ns;
}
#endif

#ifdef MODE_VISIBILITY
// The ground truth of the raster visibility buffer (debug.view=visibility): the fraction of light
// rt.fparams.w reaching the first visible point, 0 where the surface faces away from it or the
// light sends nothing its way (outside a spot cone, behind a one-sided emitter). Below
// the punctual count: that punctual light; otherwise all emissive triangles (a point drawn by
// power per sample, so the mean is the power-weighted visible fraction).
vec3 radiance(Ray ray, inout Rng rng) {
    Hit hit = trace_closest(ray, 3.0e38);
    if (hit.prim < 0) return vec3(0.0);
    SurfaceHit s = surface_at(ray, hit);
    int li = int(rt.fparams.w);
    if (li < rt.counts.w) {
        vec3 l, E;
        float dist;
        light_incidence(lights[li], s.p, l, E, dist);
        if (dot(s.ns, l) <= 0.0 || dot(s.ng, l) <= 0.0 || max(E.r, max(E.g, E.b)) <= 0.0) return vec3(0.0);
        return vec3(trace_any(make_ray(offset_ray(s.p, s.ng, rt.fparams2.x), l), dist) ? 0.0 : 1.0);
    }
#ifdef HAS_EMITTERS
    float u = rng_next(rng);
    int lo = 0, hi = rt.counts.z - 1;
    while (lo < hi) {
        int mid = (lo + hi) / 2;
        if (emitters[mid].cdf < u) lo = mid + 1; else hi = mid;
    }
    RtTriangle tri = load_triangle(int(emitters[lo].triangle));
    float su = sqrt(rng_next(rng));
    float u2 = rng_next(rng);
    vec3 q = (1.0 - su) * tri.p0.xyz + su * (1.0 - u2) * tri.p1.xyz + su * u2 * tri.p2.xyz;
    vec3 nl = normalize(cross(tri.p1.xyz - tri.p0.xyz, tri.p2.xyz - tri.p0.xyz));
    vec3 d = q - s.p;
    float cos_l = dot(nl, -d);
    if (material_double_sided(floatBitsToInt(tri.p0.w))) cos_l = abs(cos_l);
    if (dot(s.ns, d) <= 0.0 || dot(s.ng, d) <= 0.0 || cos_l <= 0.0) return vec3(0.0);
    vec3 origin = offset_ray(s.p, s.ng, rt.fparams2.x);
    vec3 target = offset_ray(q, dot(nl, -d) > 0.0 ? nl : -nl, rt.fparams2.x);
    return vec3(trace_any(make_ray(origin, target - origin), 1.0) ? 0.0 : 1.0);
#else
    return vec3(0.0);
#endif
}
#endif

#ifdef MODE_BOUNCE
// Camera rays plus one cosine-distributed closest-hit ray from each hit: the incoherent
// diffuse-bounce rays of path tracing, for the ray-rate benchmark. Returns the bounce hit's
// normal (0.5 + 0.5 n), black on a miss.
vec3 radiance(Ray ray, inout Rng rng) {
    Hit hit = trace_closest(ray, 3.0e38);
    if (hit.prim < 0) return vec3(0.0);
    SurfaceHit s = surface_at(ray, hit);
    Ray bounce = make_ray(offset_ray(s.p, s.ng, rt.fparams2.x), to_world(sample_cosine_hemisphere(vec2(rng_next(rng), rng_next(rng))), s.ng));
    Hit h2 = trace_closest(bounce, 3.0e38);
    if (h2.prim < 0) return vec3(0.0);
    return 0.5 + 0.5 * surface_at(bounce, h2).ns;
}
#endif

#ifdef MODE_AO
vec3 radiance(Ray ray, inout Rng rng) {
    Hit hit = trace_closest(ray, 3.0e38);
    if (hit.prim < 0) return vec3(1.0);
    SurfaceHit s = surface_at(ray, hit);
    vec3 dir = to_world(sample_cosine_hemisphere(vec2(rng_next(rng), rng_next(rng))), s.ng);
    bool occluded = trace_any(make_ray(offset_ray(s.p, s.ng, rt.fparams2.x), dir * rt.fparams.x), 1.0);
    return vec3(occluded ? 0.0 : 1.0);
}
#endif

#ifdef MODE_PATH
// Unidirectional path tracing with next-event estimation (punctual lights always, emissive
// triangles with MIS against BRDF sampling), Russian roulette after three bounces.
vec3 radiance(Ray ray, inout Rng rng) {
    vec3 sum = vec3(0.0);
    vec3 throughput = vec3(1.0);
    float last_brdf_pdf = 0.0;  // 0: the last bounce was specular-delta or the camera
    int max_depth = rt.params.x;
#ifdef HAS_BLEND
    int layers = 0;
#endif
    for (int depth = 0; depth <= max_depth; ++depth) {
        Hit hit = trace_closest(ray, 3.0e38);
        if (hit.prim < 0) {
            float w = 1.0;
#ifdef HAS_ENV_MAP_SAMPLING
            if (last_brdf_pdf > 0.0) w = power_heuristic(last_brdf_pdf, env_pdf(ray.dir));
#endif
            sum += throughput * environment(ray.dir) * w;
            break;
        }
        SurfaceHit s = surface_at(ray, hit);
#ifdef HAS_BLEND
        // Camera rays pass a blended layer with probability 1 - alpha: in expectation
        // alpha * (the layer) + (1 - alpha) * (what is behind it), the OVER operator.
        if (depth == 0 && layers < 32 && rng_next(rng) >= blend_alpha(s)) {
            ray = make_ray(offset_ray(s.p, -s.ng, rt.fparams2.x), ray.dir);
            ++layers;
            --depth;
            continue;
        }
#endif
        vec3 Le = emitted(s);
        if (max(Le.r, max(Le.g, Le.b)) > 0.0) {
            float w = 1.0;
#ifdef HAS_EMITTERS
            if (last_brdf_pdf > 0.0) w = power_heuristic(last_brdf_pdf, emitter_pdf(ray, hit, s));
#endif
            sum += throughput * Le * w;
        }
        if (depth == max_depth) break;
        vec3 v = -normalize(ray.dir);
#ifdef HAS_TRANSMISSION
        float transmission = material_transmission(s.material);
        if (transmission > 0.0 && rng_next(rng) < transmission) {
            // Smooth dielectric: reflect or refract by the exact Fresnel term.
            BrdfInput m = brdf_input(s);
            bool thin = material_thin(s.material);
            float eta = thin ? 1.0 : (s.front ? 1.0 / m.ior : m.ior);
            float cos_i = dot(v, s.ng);
            // A thin wall reflects like the interface it stands for but does not bend the ray.
            float F = fresnel_dielectric(cos_i, thin ? 1.0 / m.ior : eta);
            if (rng_next(rng) < F) {
                ray = make_ray(offset_ray(s.p, s.ng, rt.fparams2.x), reflect(-v, s.ng));
            } else {
                ray = make_ray(offset_ray(s.p, -s.ng, rt.fparams2.x), thin ? -v : refract(-v, s.ng, eta));
                throughput *= m.base_color;
            }
            last_brdf_pdf = 0.0;
            continue;
        }
#endif
        BrdfInput m = brdf_input(s);
        sum += throughput * direct_punctual(s, m, v);
#ifdef HAS_EMITTERS
        sum += throughput * direct_emitters(s, m, v, rng, true);
#endif
#ifdef HAS_ENV_MAP_SAMPLING
        {
            float pdf_env;
            vec3 le = sample_env(rng, pdf_env);
            vec3 fc = pdf_env > 0.0 ? brdf_cos_folded(m, s, le, v) : vec3(0.0);
            if (max(fc.r, max(fc.g, fc.b)) > 0.0 &&
                !trace_any(make_ray(offset_ray(s.p, s.ng, rt.fparams2.x), le), 3.0e38)) {
                float w = power_heuristic(pdf_env, brdf_pdf_folded(m, s, v, le));
                sum += throughput * fc * environment(le) * w / pdf_env;
            }
        }
#endif
        vec3 l;
        if (!sample_brdf_folded(m, s, v, rng, l)) break;
        float pdf = brdf_pdf_folded(m, s, v, l);
        if (pdf <= 0.0) break;
        throughput *= brdf_cos_folded(m, s, l, v) / pdf;
        last_brdf_pdf = pdf;
        if (depth >= 3) {
            float survive = clamp(max(throughput.r, max(throughput.g, throughput.b)), 0.05, 0.95);
            if (rng_next(rng) >= survive) break;
            throughput /= survive;
        }
        ray = make_ray(offset_ray(s.p, s.ng, rt.fparams2.x), l);
    }
    return sum;
}
#endif

#ifdef MODE_INDIRECT
// Light leaving y towards x after one diffuse reflection at y (Lambertian, y's diffuse albedo):
// the direct light at y, with visibility from y to the lights.
vec3 diffuse_outgoing(SurfaceHit y, vec3 to_x, inout Rng rng) {
    BrdfInput my = brdf_input(y);
    BrdfInput lambert_y = my;
    lambert_y.base_color = my.base_color * (1.0 - my.metallic);
    lambert_y.metallic = 0.0;
    lambert_y.specular_factor = 0.0;
    vec3 L = direct_punctual(y, lambert_y, to_x);
#ifdef HAS_EMITTERS
    L += direct_emitters(y, lambert_y, to_x, rng, false);
#endif
    return L;
}

// One diffuse bounce: light that reached the first visible point x after exactly one reflection
// off another surface y (Lambertian at both ends, as RSM models it). The ground truth for RSM.
vec3 radiance(Ray ray, inout Rng rng) {
    Hit hit = trace_closest(ray, 3.0e38);
    if (hit.prim < 0) return vec3(0.0);
    SurfaceHit x = surface_at(ray, hit);
    BrdfInput mx = brdf_input(x);
    vec3 albedo_x = mx.base_color * (1.0 - mx.metallic);
    if (rt.params.z != 0) {
        // With occlusion: y is what a cosine-distributed ray from x sees.
        vec3 dir = to_world(sample_cosine_hemisphere(vec2(rng_next(rng), rng_next(rng))), x.ns);
        if (dot(dir, x.ng) <= 0.0) return vec3(0.0);
        Ray bounce = make_ray(offset_ray(x.p, x.ng, rt.fparams2.x), dir);
        Hit hy = trace_closest(bounce, 3.0e38);
        if (hy.prim < 0) return vec3(0.0);
        // Cosine sampling: f_x * cos / pdf = albedo_x.
        return albedo_x * diffuse_outgoing(surface_at(bounce, hy), -dir, rng);
    }
    // Without occlusion between x and y: y uniform by area over every triangle,
    // L = f_x * L_o(y) * cos_x * cos_y / d^2 / pdf_area(y).
    if (rt.counts2.x == 0) return vec3(0.0);
    float u = rng_next(rng);
    int lo = 0, hi = rt.counts2.x - 1;
    while (lo < hi) {
        int mid = (lo + hi) / 2;
        if (surfaces[mid].cdf < u) lo = mid + 1; else hi = mid;
    }
    Emitter pick = surfaces[lo];
    RtTriangle tri = load_triangle(int(pick.triangle));
    float su = sqrt(rng_next(rng));
    float u2 = rng_next(rng);
    vec2 bary = vec2(su * (1.0 - u2), su * u2);
    vec3 q = (1.0 - su) * tri.p0.xyz + bary.x * tri.p1.xyz + bary.y * tri.p2.xyz;
    vec3 d = q - x.p;
    float dist2 = dot(d, d);
    if (dist2 <= 0.0) return vec3(0.0);
    vec3 dir = d * inversesqrt(dist2);
    float cos_x = dot(x.ns, dir);
    if (cos_x <= 0.0) return vec3(0.0);
    // The surface record at y as seen from x (front side towards x).
    Ray to_y = make_ray(x.p, d);
    Hit hy;
    hy.t = 1.0;
    hy.prim = int(pick.triangle);
    hy.bary = bary;
    SurfaceHit y = surface_at(to_y, hy);
    if (!y.front && !material_double_sided(y.material)) return vec3(0.0);
    float cos_y = dot(y.ng, -dir);
    if (cos_y <= 0.0) return vec3(0.0);
    float pdf_area = pick.pdf / pick.area;
    return albedo_x * INV_PI * diffuse_outgoing(y, -dir, rng) * cos_x * cos_y / (dist2 * pdf_area);
}
#endif

#ifdef MODE_WHITTED
// Whitted (1980): local shading with shadow rays, plus mirror reflection and refraction with the
// exact Fresnel equations, to `max depth`. The branches are kept on a small explicit stack.
vec3 radiance(Ray primary, inout Rng rng) {
    const int kMaxStack = 16;
    Ray rays[kMaxStack];
    vec3 weights[kMaxStack];
    int depths[kMaxStack];
    int n = 1;
    rays[0] = primary;
    weights[0] = vec3(1.0);
    depths[0] = 0;
    vec3 sum = vec3(0.0);
    while (n > 0) {
        --n;
        Ray ray = rays[n];
        vec3 w = weights[n];
        int depth = depths[n];
        Hit hit = trace_closest(ray, 3.0e38);
        if (hit.prim < 0) {
            sum += w * environment(ray.dir);
            continue;
        }
        SurfaceHit s = surface_at(ray, hit);
        vec3 v = -normalize(ray.dir);
#ifdef HAS_BLEND
        // A blended layer on the camera ray: alpha of it, 1 - alpha of what is behind (OVER).
        if (depth == 0) {
            float a = blend_alpha(s);
            if (a < 1.0 && n < kMaxStack) {
                rays[n] = make_ray(offset_ray(s.p, -s.ng, rt.fparams2.x), ray.dir);
                weights[n] = w * (1.0 - a);
                depths[n++] = 0;
                w *= a;
            }
        }
#endif
        BrdfInput m = brdf_input(s);
        sum += w * emitted(s);
        bool can_branch = depth < rt.params.x && n + 2 <= kMaxStack;
#ifdef HAS_TRANSMISSION
        if (material_transmission(s.material) > 0.0) {
            bool thin = material_thin(s.material);
            float eta = thin ? 1.0 : (s.front ? 1.0 / m.ior : m.ior);
            float F = fresnel_dielectric(dot(v, s.ng), thin ? 1.0 / m.ior : eta);
            if (!can_branch) continue;
            rays[n] = make_ray(offset_ray(s.p, s.ng, rt.fparams2.x), reflect(-v, s.ng));
            weights[n] = w * F;
            depths[n++] = depth + 1;
            if (F < 1.0) {
                rays[n] = make_ray(offset_ray(s.p, -s.ng, rt.fparams2.x), thin ? -v : refract(-v, s.ng, eta));
                weights[n] = w * (1.0 - F) * m.base_color;
                depths[n++] = depth + 1;
            }
            continue;
        }
#endif
        // Local: punctual and area lights with shadow rays, and the unoccluded environment as an
        // ambient term on the diffuse part.
        sum += w * direct_punctual(s, m, v);
#ifdef HAS_EMITTERS
        sum += w * direct_emitters(s, m, v, rng, false);
#endif
        sum += w * environment(s.ns) * m.base_color * (1.0 - m.metallic);
        if (m.roughness <= rt.fparams.y && can_branch) {
            // Mirror reflection weighted by the BRDF's Fresnel at normal-vector incidence.
            float cos_v = saturate(dot(v, s.ns));
            vec3 F = mix(F_Schlick(dielectric_f0(m), vec3(dielectric_f90(m)), cos_v),
                         F_Schlick(m.base_color, vec3(1.0), cos_v), m.metallic);
            // The mirror direction about ns, folded above the geometric surface as path mode
            // folds its BRDF (see fold_above).
            rays[n] = make_ray(offset_ray(s.p, s.ng, rt.fparams2.x), fold_above(reflect(-v, s.ns), s.ng));
            weights[n] = w * F;
            depths[n++] = depth + 1;
        }
    }
    return sum;
}
#endif

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy) + ivec2(0, rt.params.w);
    if (pixel.x >= rt.image.x || pixel.y >= rt.image.y) return;
    uint index = uint(pixel.y * rt.image.x + pixel.x);
    Rng rng = rng_init(uint(rt.image.w), index, uint(rt.image.z));
    Ray ray = camera_ray(pixel, rng);
    vec3 L = radiance(ray, rng);
    if (any(isnan(L)) || any(isinf(L))) {
        atomicAdd(nonfinite_samples, 1u);
        L = vec3(0.0);
    }
    accum[index] += vec4(L, 1.0);
}
