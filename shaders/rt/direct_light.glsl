// Direct light at a surface point: punctual lights with shadow rays, and (HAS_EMITTERS) one
// emissive triangle or sphere chosen by power, with MIS against BRDF sampling, plus the pdf
// BRDF rays need for that MIS.
#include "brdf_sampling.glsl"

// What fraction of light gets through along a shadow ray from a surface to a light (tmax: the
// light's distance along ray.dir). Each mode that uses direct light defines it: whitted lets
// light through transmissive surfaces (transparent shadows), the others call opaque_visibility.
vec3 shadow_visibility(Ray ray, float tmax);

// Plain visibility: every surface blocks the light.
vec3 opaque_visibility(Ray ray, float tmax) {
    return trace_any(ray, tmax) ? vec3(0.0) : vec3(1.0);
}

vec3 direct_punctual(SurfaceHit s, BrdfInput m, vec3 v) {
    vec3 sum = vec3(0.0);
    for (int i = 0; i < rt.punctual_light_count; ++i) {
        vec3 l, E;
        float dist;
        light_incidence(lights[i], s.p, l, E, dist);
        if (max(E.r, max(E.g, E.b)) <= 0.0) continue;
        vec3 fc = brdf_cos_folded(m, s, l, v);
        if (max(fc.r, max(fc.g, fc.b)) <= 0.0) continue;
        vec3 visible = shadow_visibility(make_ray(offset_ray(s.p, s.ng, rt.ray_offset), l), dist);
        sum += fc * E * visible;
    }
    return sum;
}

// The punctual lights reflected by the specular lobe alone, about the geometric normal: what a
// dielectric interface (KHR_materials_transmission) reflects of them. A path that meets the
// interface reflects or refracts by sampling, and a sampled direction never finds a delta light,
// so without this the tracer showed no highlight of a point, spot or directional light on glass
// where the raster does (its shade_light keeps the specular lobe of a transmissive surface).
vec3 direct_punctual_specular(SurfaceHit s, BrdfInput m, vec3 v) {
    vec3 sum = vec3(0.0);
    if (dot(s.ng, v) <= 0.0) return sum;
    for (int i = 0; i < rt.punctual_light_count; ++i) {
        vec3 l, E;
        float dist;
        light_incidence(lights[i], s.p, l, E, dist);
        float c = dot(s.ng, l);
        if (c <= 0.0 || max(E.r, max(E.g, E.b)) <= 0.0) continue;
        vec3 fc = brdf_eval_weighted(m, s.ng, l, v, 0.0) * c;
        if (max(fc.r, max(fc.g, fc.b)) <= 0.0) continue;
        sum += fc * E * shadow_visibility(make_ray(offset_ray(s.p, s.ng, rt.ray_offset), l), dist);
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
    RtSphere sp = spheres[int(e.triangle) - rt.triangle_count];
    vec3 c = sp.center;
    float r = sp.radius;
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
    int mat = sp.material;
    vec3 Le = materials[mat].emission;
    float pdf = e.pdf / (2.0 * PI * omc);
    vec3 origin = offset_ray(s.p, s.ng, rt.ray_offset);
    vec3 target = offset_ray(q, nl, rt.ray_offset);
    vec3 visible = shadow_visibility(make_ray(origin, target - origin), 1.0);
    float w = use_mis ? power_heuristic(pdf, brdf_pdf_folded(m, s, v, l)) : 1.0;
    return fc * Le * w * visible / pdf;
}

// One emitter chosen by power: an emissive triangle (one point on it uniformly by area) or an
// emissive sphere (direct_sphere); MIS with the BRDF.
vec3 direct_emitters(SurfaceHit s, BrdfInput m, vec3 v, inout Rng rng, bool use_mis) {
    float u = rng_next(rng);
    int lo = 0, hi = rt.emitter_count - 1;
    while (lo < hi) {
        int mid = (lo + hi) / 2;
        if (emitters[mid].cdf < u) lo = mid + 1; else hi = mid;
    }
    Emitter e = emitters[lo];
#ifndef RT_NO_SPHERES
    if (int(e.triangle) >= rt.triangle_count) return direct_sphere(s, m, v, rng, use_mis, e);
#endif
    RtTriangle tri = load_triangle(int(e.triangle));
    float su = sqrt(rng_next(rng));
    float u2 = rng_next(rng);
    vec3 q = (1.0 - su) * tri.p0.xyz + su * (1.0 - u2) * tri.p1.xyz + su * u2 * tri.p2.xyz;
    vec3 nl = normalize(cross(tri.p1.xyz - tri.p0.xyz, tri.p2.xyz - tri.p0.xyz));
    int mat = floatBitsToInt(tri.p0.w);
    // The emission at the sampled point, with the emissive texture, as a BRDF ray would see it
    // (the emitter was chosen by its untextured power: still unbiased where the texture is > 0).
    vec3 Le = materials[mat].emission;
#ifndef RT_NO_TEXTURES
    if (materials[mat].emissive_texcoord >= 0) {
        vec2 b = vec2(su * (1.0 - u2), su * u2);
        float w0 = 1.0 - b.x - b.y;
        vec2 uv0 = tri.uv_a.xy * w0 + tri.uv_a.zw * b.x + tri.uv_b.xy * b.y;
        vec2 uv1 = tri.uv_b.zw * w0 + tri.uv_c.xy * b.x + tri.uv_c.zw * b.y;
        MaterialData me = materials[mat];
        Le *= material_texture(me, 4, me.emissive_image, me.emissive_texcoord, uv0, uv1).rgb;
    }
#endif
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
    vec3 origin = offset_ray(s.p, s.ng, rt.ray_offset);
    vec3 target = offset_ray(q, dot(nl, -l) > 0.0 ? nl : -nl, rt.ray_offset);
    vec3 visible = shadow_visibility(make_ray(origin, target - origin), 1.0);
    float w = use_mis ? power_heuristic(pdf, brdf_pdf_folded(m, s, v, l)) : 1.0;
    return fc * Le * w * visible / pdf;
}

// Solid-angle pdf with which direct_emitters would have chosen the point the BRDF ray hit.
float emitter_pdf(Ray ray, Hit hit, SurfaceHit s) {
#ifndef RT_NO_SPHERES
    if (hit.prim >= rt.triangle_count) {
        RtSphere sp = spheres[hit.prim - rt.triangle_count];
        float select = sp.emitter_pdf;
        vec3 dc = sp.center - ray.origin;
        float d2 = dot(dc, dc), r = sp.radius;
        if (select <= 0.0 || d2 <= r * r) return 0.0;
        return select / (2.0 * PI * sphere_cone_one_minus_cos(r, d2));
    }
#endif
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

// Light leaving y towards x after one diffuse reflection at y (Lambertian, y's diffuse albedo):
// the direct light at y, with visibility from y to the lights. The indirect mode's bounce points
// use it (the GI probes' hits take the full BRDF: direct_punctual, direct_emitters). Needs
// shadow_visibility; with HAS_EMITTERS, one emitter sample.
vec3 lambert_direct_light(SurfaceHit y, vec3 to_x, inout Rng rng) {
    BrdfInput my = brdf_input(y);
    BrdfInput lambert_y = my;
    lambert_y.base_color = my.base_color * (1.0 - my.metallic);
    lambert_y.metallic = 0.0;
    lambert_y.specular_factor = 0.0;
    vec3 L = direct_punctual(y, lambert_y, to_x);
#ifdef HAS_EMITTERS
    if (rt.emitter_count > 0) L += direct_emitters(y, lambert_y, to_x, rng, false);
#endif
    return L;
}
