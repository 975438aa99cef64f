// Polygon lights shaded by linearly transformed cosines (included by shaders/lighting/shading.glsl
// through the registry: hooks direct_light and shaded_light_count).
// Heitz, Dupuy, Hill & Neubelt 2016, "Real-Time Polygonal-Light Shading with Linearly
// Transformed Cosines": the integral of a GGX lobe times the cosine over a polygon equals the
// integral of a clamped cosine over the polygon transformed by M^-1, which has a closed form
// (Lambert's formula for the irradiance from a polygon). The tables come from Candela's own BRDF
// (engine/effects/area_lights/ltc.hpp, fitted by effects/area_lights/ltc_fit).
// Shadows: Heitz, Hill & McGuire 2018, "Combining Analytic Direct Illumination and Stochastic
// Shadows": the unshadowed LTC value times a ratio of shadowed to unshadowed estimates, here
// those of the emitter's pieces (the shadowed point lights of the pieces method), so an
// unoccluded point receives exactly the LTC value.
#include "effects/area_lights/area_lights_data.h"

layout(std430, binding = AREA_POLYGONS_BINDING) readonly buffer PolygonLights { PolygonLight polygon_lights[]; };
layout(binding = LTC_MATRIX_UNIT) uniform sampler2D t_ltc_matrix;
layout(binding = LTC_AMPLITUDE_UNIT) uniform sampler2D t_ltc_amplitude;

// The lights the per-light loops shade one by one (hook shaded_light_count): with LTC the pieces
// only cast shadows.
int area_lights_shaded_light_count() { return area_lights.method == 1 ? frame.punctual_light_count : frame.light_count; }

// The vector form factor of the great-circle edge a->b (any non-zero lengths):
// theta * normalize(a x b), theta the angle between a and b, stable near 0.
vec3 ltc_edge_vector(vec3 a, vec3 b) {
    a = normalize(a);
    b = normalize(b);
    vec3 c = cross(a, b);
    float s = length(c);
    float theta = atan(s, dot(a, b));
    return c * (s > 1e-7 ? theta / s : 1.0);
}

// The polygon's vector form factor in its frame: sum over the edges (a, b) of the polygon spanned
// by L0..L2 or L0..L3 (any lengths), clipped to z >= 0, of theta * normalize(a x b) / (2 pi). Its z is the
// integral of the normalised clamped cosine (z / pi) over the polygon (Lambert's formula), signed
// by the winding; its direction is the cosine-weighted mean direction of the light.
// The clipped polygon is walked edge by edge without storing it: each edge keeps its part above
// the horizon, and a triangle crosses the horizon at most once each way, so one horizon edge joins
// the exit point to the entry point. (A local array indexed by a running count is what this
// replaces: CPU rasterisers such as llvmpipe keep such arrays in memory, and the lookup cost most
// of a frame.)
void ltc_clipped_edge(vec3 a, vec3 b, inout vec3 sum, inout vec3 exit_point, inout vec3 entry_point) {
    bool a_up = a.z >= 0.0, b_up = b.z >= 0.0;
    if (a_up && b_up) {
        sum += ltc_edge_vector(a, b);
    } else if (a_up || b_up) {
        vec3 x = mix(a, b, a.z / (a.z - b.z));
        if (a_up) {
            sum += ltc_edge_vector(a, x);
            exit_point = x;
        } else {
            sum += ltc_edge_vector(x, b);
            entry_point = x;
        }
    }
}

// A triangle (quad false) or a convex quad L0..L3: a convex polygon too crosses the horizon at
// most once each way.
vec3 ltc_polygon_vector(vec3 L0, vec3 L1, vec3 L2, vec3 L3, bool quad) {
    vec3 last = quad ? L3 : L2;
    if (L0.z < 0.0 && L1.z < 0.0 && L2.z < 0.0 && last.z < 0.0) return vec3(0.0);
    vec3 sum = vec3(0.0), exit_point = vec3(0.0), entry_point = vec3(0.0);
    ltc_clipped_edge(L0, L1, sum, exit_point, entry_point);
    ltc_clipped_edge(L1, L2, sum, exit_point, entry_point);
    if (quad) ltc_clipped_edge(L2, L3, sum, exit_point, entry_point);
    ltc_clipped_edge(last, L0, sum, exit_point, entry_point);
    if (L0.z < 0.0 || L1.z < 0.0 || L2.z < 0.0 || last.z < 0.0) sum += ltc_edge_vector(exit_point, entry_point);
    return sum / (2.0 * PI);
}

// Texture coordinates of (roughness, NdotV) in the table: ltc.hpp's table_coords, the same formula.
vec2 ltc_table_coords(float roughness, float NdotV) {
    float u = acos(clamp(NdotV, 0.0, 1.0)) * 0.63661977236758134;  // theta / (pi / 2)
    vec2 rt = vec2(clamp(roughness, 0.0, 1.0), u * (0.5 + 0.5 * u));
    float n = float(area_lights.ltc_size);
    return (rt * (n - 1.0) + 0.5) / n;
}

// The fitted M^-1 for this roughness and view angle (layout: engine/effects/area_lights/ltc.hpp).
mat3 ltc_matrix(float roughness, float NdotV, out vec2 amplitude) {
    vec2 uv = ltc_table_coords(roughness, NdotV);
    vec4 m = texture(t_ltc_matrix, uv);
    amplitude = texture(t_ltc_amplitude, uv).rg;
    // Columns of the GLSL matrix: M^-1 = [[m.x, 0, m.y], [0, m.z, 0], [m.w, 0, 1]] (rows).
    return mat3(vec3(m.x, 0.0, m.w), vec3(0.0, m.z, 0.0), vec3(m.y, 0.0, 1.0));
}

// The share of an emitter's light that reaches p: its pieces' shadowed over unshadowed Lambert
// estimates (1 exactly where no piece is shadowed). Pieces all below p's horizon: their plain mean.
// A piece with no Lambert weight adds nothing to either sum, so its shadow (the costly part: a
// filtered shadow-map lookup) is only looked up when no piece has weight and the plain mean is
// the answer; the sums, and so the ratio, are those of summing over every piece.
float area_visibility(int first, int count, vec3 p, vec3 n, vec2 pixel) {
    // No piece with a shadow map (shadows off, or the emitter beyond shadows.max_lights or the
    // shadow budget): every piece's visibility is 1, and so is the ratio.
    bool any_shadowed = false;
    for (int k = first; k < first + count && !any_shadowed; ++k) any_shadowed = lights[k].shadow_view_count > 0.5;
    if (!any_shadowed) return 1.0;
    bool any_weight = false;
    for (int k = first; k < first + count && !any_weight; ++k) {
        vec3 l, E;
        float dist;
        light_incidence(lights[k], p, l, E, dist);
        any_weight = max(dot(n, l), 0.0) * (E.r + E.g + E.b) > 0.0;
    }
    float shadowed = 0.0, unshadowed = 0.0, plain = 0.0;
    for (int k = first; k < first + count; ++k) {
        LightData light = lights[k];
        vec3 l, E;
        float dist;
        light_incidence(light, p, l, E, dist);
        float w = max(dot(n, l), 0.0) * (E.r + E.g + E.b);
        if (any_weight && !(w > 0.0)) continue;
        float s = effect_light_visibility(light, p, n, l, pixel);
        shadowed += w * s;
        unshadowed += w;
        plain += s;
    }
    if (unshadowed > 0.0) return shadowed / unshadowed;
    return count > 0 ? plain / float(count) : 1.0;
}

// The specular the LTC misses over one polygon (a control variate): the lobe's integral over the
// polygon is the LTC's plus that of the residual f cos - norm D_ltc. Here the polygon is cut into
// kResidualCells^2 cells (a triangle is the quad p0 p1 p2 p2); on each, the lobe's integral is
// taken by the midpoint rule and the LTC's exactly, so the residual carries the quadrature's error
// of the true lobe alone. A clamped cosine cannot take GGX's shape at grazing views nor its tail
// near the horizon, where f cos stays finite while every cosine goes to 0: a large emitter seen
// only in a smooth metal's tail was 5x too dark, a quad towards the viewer of a grazing rough
// metal 1.5x too bright. Where the midpoint cannot resolve the lobe (its value times the cell's
// solid angle is more than kResidualShare of the lobe's albedo: a sharp highlight) the cell's
// residual fades out and the LTC answers there. Returns the residual with F = 1, in units of
// the polygon's radiance; the caller weighs it with its specular Fresnel.
const int kResidualCells = 3;
const float kResidualShare = 0.03;
const float kResidualMinSpecular = 0.1;
vec3 residual_corner(vec3 a, vec3 b, vec3 c, vec3 d, int i, int j) {
    float u = float(i) / float(kResidualCells), t = float(j) / float(kResidualCells);
    return mix(mix(a, b, u), mix(d, c, u), t);
}
float ltc_residual(vec3 a, vec3 b, vec3 c, vec3 d, float two_sided, vec3 n, vec3 v, float alpha, mat3 m_inv, float norm) {
    float NdotV = dot(n, v);
    if (NdotV <= 0.0) return 0.0;  // brdf.glsl's lobe is 0 there
    float sum = 0.0;
    for (int j = 0; j < kResidualCells; ++j)
        for (int i = 0; i < kResidualCells; ++i) {
            vec3 c00 = residual_corner(a, b, c, d, i, j), c10 = residual_corner(a, b, c, d, i + 1, j);
            vec3 c11 = residual_corner(a, b, c, d, i + 1, j + 1), c01 = residual_corner(a, b, c, d, i, j + 1);
            vec3 q = 0.25 * (c00 + c10 + c11 + c01);  // relative to the shaded point
            vec3 area = 0.5 * cross(c11 - c00, c01 - c10);  // the cell's area-weighted normal (winding's side)
            float dist2 = dot(q, q);
            if (!(dist2 > 0.0)) continue;
            vec3 l = q * inversesqrt(dist2);
            float cos_e = -dot(area, l);
            if (two_sided > 0.5) cos_e = abs(cos_e);
            float NdotL = dot(n, l);
            float f = 0.0;
            if (NdotL > 0.0 && cos_e > 0.0) {
                vec3 h = normalize(l + v);
                f = D_GGX(saturate(dot(n, h)), alpha) * V_SmithGGXCorrelated(NdotL, NdotV, alpha) * NdotL * cos_e / dist2;
            }
            float g = norm * abs(ltc_polygon_vector(m_inv * c00, m_inv * c10, m_inv * c11, m_inv * c01, true).z);
            float weight = saturate(1.0 - max(f, g) / (max(norm, 1e-4) * kResidualShare));
            sum += (f - g) * weight;
        }
    return sum;
}

// Light from the polygon lights towards v, with each emitter's visibility ratio (hook direct_light).
vec3 area_lights_direct_light(BrdfInput bi, vec3 p, vec3 n, vec3 v, vec2 pixel, float transmission) {
#ifdef AREA_LIGHTS_OFF
    return vec3(0.0);  // no polygon to shade (area_lights.cpp)
#else
    if (area_lights.method != 1 || area_lights.polygon_count == 0) return vec3(0.0);
    float NdotV = saturate(dot(n, v));
    // The frame of the table: z = n, x towards v (v in the xz plane).
    vec3 t1 = v - n * dot(v, n);
    t1 = dot(t1, t1) > 1e-12 ? normalize(t1) : (abs(n.x) < 0.9 ? normalize(cross(n, vec3(1, 0, 0))) : normalize(cross(n, vec3(0, 1, 0))));
    vec3 t2 = cross(n, t1);
    mat3 to_local = transpose(mat3(t1, t2, n));
    vec3 v_local = vec3(sqrt(max(1.0 - NdotV * NdotV, 0.0)), 0.0, NdotV);
    vec2 amplitude;
    mat3 m_inv_local = ltc_matrix(bi.roughness, max(NdotV, 1e-4), amplitude);
    mat3 m_local = inverse(m_inv_local);
    mat3 m_inv = m_inv_local * to_local;
    // The residual changes a pixel by at most its specular reflectance times the lobe's mismatch:
    // where that reflectance (Schlick's at the view's angle) is under kResidualMinSpecular, as on
    // a dielectric seen away from grazing, the residual is not worth its cells.
    vec3 spec_view = mix(F_Schlick(dielectric_f0(bi), vec3(dielectric_f90(bi)), NdotV), F_Schlick(bi.base_color, vec3(1.0), NdotV), bi.metallic);
    bool with_residual = area_lights.residual != 0 && max(spec_view.r, max(spec_view.g, spec_view.b)) >= kResidualMinSpecular;
    float alpha = brdf_alpha(bi.roughness);
    vec3 f0_d = dielectric_f0(bi);
    float f90_d = dielectric_f90(bi);
    vec3 sum = vec3(0.0);
    vec3 group_sum = vec3(0.0);
    int group = -1;
    // One pass beyond the last polygon closes the last emitter, so that area_visibility (and the
    // shadow lookups in it) has one call site. An emitter none of whose polygons adds light here
    // (all facing away or clipped away) adds 0 whatever its visibility: that is not looked up.
    int count = area_lights.polygon_count;
    for (int i = 0; i <= count; ++i) {
        int first = i < count ? int(polygon_lights[i].first_piece) : -2;
        if (first != group) {
            if (group >= 0 && any(notEqual(group_sum, vec3(0.0))))
                sum += group_sum * area_visibility(group, int(polygon_lights[i - 1].piece_count), p, n, pixel);
            if (i == count) break;
            group = first;
            group_sum = vec3(0.0);
        }
        PolygonLight pl = polygon_lights[i];
        vec3 a = pl.p0 - p, b = pl.p1 - p, c = pl.p2 - p, d = pl.p3 - p;
        bool quad = pl.corners > 3.5;
        // One-sided: only the side the winding's normal points to emits.
        float facing = dot(cross(b - a, c - a), -a);
        if (pl.double_sided < 0.5 && facing <= 0.0) continue;
        // Far field (arealight.far_field): a polygon of angular radius t = R / d below 1 / far_field
        // and below a quarter of the lobe's width alpha is a point emitter: radiance times its
        // solid angle (area times cosine over d^2) through the BRDF. For a uniform disk the
        // irradiance is the point's times 1 / (1 + t^2); across a quarter of the lobe's width the
        // GGX lobe changes by a few per cent. It skips the two polygon integrals and the residual.
        if (area_lights.far_field > 0.0) {
            vec3 centre = quad ? 0.25 * (a + b + c + d) : (a + b + c) * (1.0 / 3.0);
            float d2 = dot(centre, centre);
            float r2 = max(max(dot(a - centre, a - centre), dot(b - centre, b - centre)),
                           max(dot(c - centre, c - centre), quad ? dot(d - centre, d - centre) : 0.0));
            float t_max = min(1.0 / area_lights.far_field, 0.25 * alpha);
            if (r2 < t_max * t_max * d2) {
                vec3 area_vector = quad ? 0.5 * cross(c - a, d - b) : 0.5 * cross(b - a, c - a);  // the winding's side
                vec3 l = centre * inversesqrt(d2);
                float cos_e = -dot(area_vector, l);
                if (pl.double_sided > 0.5) cos_e = abs(cos_e);
                float NdotL = dot(n, l);
                if (cos_e > 0.0 && NdotL > 0.0)
                    group_sum += pl.radiance * brdf_eval_base(bi, n, l, v, 1.0 - transmission) * (NdotL * cos_e / d2);
                continue;
            }
        }
        vec3 form = ltc_polygon_vector(to_local * a, to_local * b, to_local * c, to_local * d, quad);
        float diffuse = abs(form.z);
        vec3 spec_form = ltc_polygon_vector(m_inv * a, m_inv * b, m_inv * c, m_inv * d, quad);
        float specular = abs(spec_form.z) * amplitude.x;  // times the lobe's albedo (F = 1)
        // Schlick's Fresnel at the light's mean direction within the lobe (the vector form factor
        // taken back through M), not the lobe's average: a small light sees one F.
        vec3 l_spec = m_local * (spec_form.z < 0.0 ? -spec_form : spec_form);
        l_spec = dot(l_spec, l_spec) > 0.0 ? normalize(l_spec) : vec3(0.0, 0.0, 1.0);
        float VdotHs = saturate(dot(v_local, normalize(v_local + l_spec)));
        vec3 spec_d = F_Schlick(f0_d, vec3(f90_d), VdotHs);
        vec3 spec_m = F_Schlick(bi.base_color, vec3(1.0), VdotHs);
        // The Lambert lobe keeps 1 - F(v.h) of the light (brdf.glsl), h halfway between v and
        // the light's cosine-weighted mean direction (the vector form factor's).
        float lf = length(form);
        vec3 l_mean = lf > 0.0 ? (form.z < 0.0 ? -form : form) / lf : vec3(0.0, 0.0, 1.0);
        float VdotH = saturate(dot(v_local, normalize(v_local + l_mean)));
        vec3 dielectric = (1.0 - F_Schlick(f0_d, vec3(f90_d), VdotH)) * bi.base_color * diffuse * (1.0 - transmission) + spec_d * specular;
        vec3 metal = spec_m * specular;
        vec3 light = mix(dielectric, metal, bi.metallic);
        if (with_residual) {
            float r = ltc_residual(a, b, c, quad ? d : c, pl.double_sided, n, v, alpha, m_inv, amplitude.x);
            light = max(light + mix(spec_d, spec_m, bi.metallic) * r, vec3(0.0));
        }
        group_sum += pl.radiance * light;
    }
    return sum;
#endif
}
