// Fitting linearly transformed cosines to Candela's GGX specular lobe (ltc.hpp says what and in
// which frame). The method follows Heitz, Dupuy, Hill & Neubelt 2016, section 4: for each
// (roughness, view angle), Nelder-Mead over M's free parameters (below), minimising an Lp norm of
// the difference between the normalised lobe and the LTC (p = 1.5 here, the paper's is 3: see
// kFitPower), the integral estimated with both
// distributions' samples combined by the balance heuristic; the initial guess is the neighbouring
// entry (previous view angle, or the next rougher entry at normal incidence) or a cosine turned to
// the lobe's average direction, whichever fits better. All sample sets are fixed grids, so the
// objective and the table are deterministic.
#include "effects/area_lights/ltc.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <thread>

#include "rt/sampling.hpp"

namespace candela::ltc {
namespace {

constexpr double kPi = 3.14159265358979323846;
// The last row (90 degrees) is fitted at this NdotV: at exactly 0 brdf.glsl's lobe is 0 (its
// NdotV <= 0 test), the limit from above is not. Same floor as the split-sum LUT (brdf_lut.comp).
constexpr float kMinCos = 1e-4f;
constexpr int kFitGrid = 32;     // per-axis samples of each distribution in the fit objective
// The norm minimised by the fit. The paper's L3 favours the lobe's peak; a polygon integral's error
// is bounded by half the L1 distance instead. At grazing views no LTC matches the GGX lobe (the
// best L1 any M reaches, by a grid search of all four parameters, is 0.27 at r = 0.48, NdotV =
// 0.25, where the L3 fit had 0.35 and gave 8x the exact integral of a quad towards the viewer), and
// the choice of norm trades the peak against the tails. Measured on polygon integrals of quads
// around the hemisphere (tests/unit/test_ltc.cpp), p = 1 loses 28 % on a small quad at the peak,
// p = 1.5 keeps it within 8 % and has the smallest worst error of the three (0.021 of the albedo
// against 0.034 for p = 3 and 0.028 for p = 1 at that entry).
constexpr double kFitPower = 1.5;
constexpr int kErrorGrid = 96;   // the same, for the reported L1 residual
constexpr int kAlbedoGrid = 256;  // norm/fresnel quadrature

float alpha_of(float roughness) { return std::max(roughness * roughness, 1e-3f); }  // brdf_alpha

// brdf.glsl's D_GGX * V_SmithGGXCorrelated * NdotL in double precision (the float shader loses the
// peak of the sharpest lobes: 1 - NdotH is ~1e-6 there, a float ulp of a direction ~6e-8).
double lobe_cos(double alpha, const glm::dvec3& v, const glm::dvec3& l) {
    const double NdotL = l.z, NdotV = v.z;
    if (NdotL <= 0.0 || NdotV <= 0.0) return 0.0;
    const glm::dvec3 h = glm::normalize(l + v);
    const double NdotH = std::clamp(h.z, 0.0, 1.0);
    const double a2 = alpha * alpha;
    const double d = NdotH * NdotH * (a2 - 1.0) + 1.0;
    const double D = a2 / (kPi * d * d);
    const double gv = NdotL * std::sqrt(NdotV * NdotV * (1.0 - a2) + a2);
    const double gl = NdotV * std::sqrt(NdotL * NdotL * (1.0 - a2) + a2);
    const double V = gv + gl > 0.0 ? 0.5 / (gv + gl) : 0.0;
    return D * V * NdotL;
}

glm::dmat3 m_inv_matrix(const glm::dvec4& m) {
    // glm is column-major: dmat3(col0, col1, col2).
    return glm::dmat3(glm::dvec3(m.x, 0.0, m.w), glm::dvec3(0.0, m.z, 0.0), glm::dvec3(m.y, 0.0, 1.0));
}

double ltc_value(const glm::dmat3& m_inv, double det_abs, const glm::dvec3& w) {
    const glm::dvec3 wo = m_inv * w;
    const double len2 = glm::dot(wo, wo);
    if (wo.z <= 0.0 || len2 <= 0.0) return 0.0;
    const double len = std::sqrt(len2);
    return (wo.z / len) / kPi * det_abs / (len2 * len);
}

// VNDF pdf of a reflected direction l (Heitz 2018): G1(v) D(h) / (4 NdotV), written so that it
// stays finite at NdotV = 0; 0 where h is below the surface.
double vndf_pdf(double alpha, const glm::dvec3& v, const glm::dvec3& l) {
    const glm::dvec3 hs = v + l;
    const double len = glm::length(hs);
    if (len <= 0.0) return 0.0;
    const double NdotH = hs.z / len;
    if (NdotH <= 0.0) return 0.0;
    const double a2 = alpha * alpha;
    const double d = NdotH * NdotH * (a2 - 1.0) + 1.0;
    const double D = a2 / (kPi * d * d);
    const double NdotV = v.z;
    return D / (2.0 * (NdotV + std::sqrt(a2 + (1.0 - a2) * NdotV * NdotV)));
}

struct Lobe {
    float roughness;
    double alpha;
    glm::dvec3 v;
    double norm = 0.0, fresnel = 0.0;
    glm::dvec3 average{0.0, 0.0, 1.0};  // normalised average direction of the lobe
};

// Norm, Fresnel moment and average direction by stratified sampling of GGX visible normals
// (Heitz 2018, engine/rt/sampling.hpp), one jittered sample per cell of a 256 x 256 grid (fixed
// hash, so deterministic): integral f cos dl = E[f cos / pdf], pdf = G1(v) D / (4 NdotV); the
// weight (G2 / G1) is bounded. Measured at r = 0.19, NdotV = 0.99: jittered 256^2 is 1.7e-4 from
// the converged value, cell midpoints were 1.4e-3 off (they converge as 1/n: the visible-normal
// warp is not smooth). A first version integrated over the normal distribution's CDF, whose cells
// squeeze the horizon of grazing views into the last few: 1.7e-2 off at NdotV = 1e-4.
void integrate_lobe(Lobe& lobe) {
    const glm::vec3 v(lobe.v);
    double norm = 0.0, fresnel = 0.0;
    glm::dvec3 avg(0.0);
    std::uint32_t seed = 12345u;
    auto jitter = [&seed] {
        seed = rt::pcg_hash(seed);
        return float(seed >> 8) * (1.0f / 16777216.0f);
    };
    for (int a = 0; a < kAlbedoGrid; ++a)
        for (int b = 0; b < kAlbedoGrid; ++b) {
            const glm::vec2 u((a + jitter()) / kAlbedoGrid, (b + jitter()) / kAlbedoGrid);
            const glm::dvec3 h(rt::sample_ggx_vndf(v, float(lobe.alpha), u));
            const glm::dvec3 l = glm::normalize(2.0 * glm::dot(lobe.v, h) * h - lobe.v);
            const double pdf = vndf_pdf(lobe.alpha, lobe.v, l);
            if (l.z <= 0.0 || !(pdf > 0.0)) continue;
            const double w = lobe_cos(lobe.alpha, lobe.v, l) / pdf;
            const double VdotH = std::clamp(glm::dot(lobe.v, glm::normalize(lobe.v + l)), 0.0, 1.0);
            norm += w;
            fresnel += w * std::pow(1.0 - VdotH, 5.0);
            avg += w * l;
        }
    const double n = double(kAlbedoGrid) * kAlbedoGrid;
    lobe.norm = norm / n;
    lobe.fresnel = fresnel / n;
    avg.y = 0.0;  // 0 by symmetry
    if (glm::length(avg) > 0.0) lobe.average = glm::normalize(avg);
}

// Fixed sample sets of one entry: the lobe's VNDF samples (with their normalised lobe value and
// both pdfs' BRDF part) and the cosine samples that each candidate M maps to LTC samples.
struct Samples {
    int grid = 0;
    std::vector<glm::dvec3> brdf_dir;
    std::vector<double> brdf_value, brdf_pdf;  // f / norm and VNDF pdf at the BRDF samples
    std::vector<glm::dvec3> cosine_dir;        // cosine-distributed, before the transform
};

Samples make_samples(const Lobe& lobe, int grid) {
    Samples s;
    s.grid = grid;
    const glm::vec3 v(lobe.v);
    for (int a = 0; a < grid; ++a)
        for (int b = 0; b < grid; ++b) {
            const glm::vec2 u((a + 0.5f) / grid, (b + 0.5f) / grid);
            const glm::vec3 h = rt::sample_ggx_vndf(v, float(lobe.alpha), u);
            const glm::dvec3 l = glm::normalize(2.0 * glm::dot(lobe.v, glm::dvec3(h)) * glm::dvec3(h) - lobe.v);
            s.brdf_dir.push_back(l);
            s.brdf_value.push_back(lobe_cos(lobe.alpha, lobe.v, l) / lobe.norm);
            s.brdf_pdf.push_back(vndf_pdf(lobe.alpha, lobe.v, l));
            s.cosine_dir.push_back(glm::dvec3(rt::sample_cosine_hemisphere(u)));
        }
    return s;
}

double power(double x, double p) {
    return p == 1.5 ? x * std::sqrt(x) : p == 3.0 ? x * x * x : p == 1.0 ? x : std::pow(x, p);
}

// Integral over the sphere of |f/norm - D_ltc|^p (balance heuristic of both sample sets).
double distance(const Lobe& lobe, const Samples& s, const glm::dvec4& m_inv, double p) {
    const glm::dmat3 mi = m_inv_matrix(m_inv);
    const double det = glm::determinant(mi);
    if (!(det > 0.0) || !std::isfinite(det)) return 1e300;
    const glm::dmat3 m = glm::inverse(mi);
    double sum = 0.0;
    for (size_t k = 0; k < s.brdf_dir.size(); ++k) {
        const double d = ltc_value(mi, det, s.brdf_dir[k]);
        const double pdf = s.brdf_pdf[k] + d;
        if (pdf > 0.0) sum += power(std::abs(s.brdf_value[k] - d), p) / pdf;
    }
    for (const glm::dvec3& wo : s.cosine_dir) {
        const glm::dvec3 w = glm::normalize(m * wo);
        const double d = ltc_value(mi, det, w);
        const double f = lobe_cos(lobe.alpha, lobe.v, w) / lobe.norm;
        const double pdf = vndf_pdf(lobe.alpha, lobe.v, w) + d;
        if (pdf > 0.0) sum += power(std::abs(f - d), p) / pdf;
    }
    return sum / double(s.brdf_dir.size());
}

// The optimised matrix: M = R * S, R the rotation about Y that turns +Z to the lobe's average
// direction (as in the paper; it puts every start on the lobe) followed by a rotation by a free
// angle phi about Y, and S = [[a, 0, b], [0, c, 0], [0, 0, 1]] (a, c: widths, b: skew). The
// optimisation variables are (ln a, b / a, ln c, phi), better conditioned than the raw entries
// (which reach 1e3 and more for the sharpest lobes). The extra angle lowered the L1 residual of
// rough grazing entries (r = 0.5, 76 degrees: 0.46 -> 0.34) at no loss elsewhere. Returned as M^-1
// normalised to m22 = 1.
glm::dmat3 axis_rotation(const glm::dvec3& axis) {
    const double c = axis.z, s = -axis.x;  // R e_z = (-s, 0, c) = axis
    return glm::dmat3(glm::dvec3(c, 0.0, s), glm::dvec3(0.0, 1.0, 0.0), glm::dvec3(-s, 0.0, c));
}

glm::dvec4 m_inv_of(const glm::dmat3& base, const glm::dvec4& p) {
    const double ca = std::cos(p.w), sa = std::sin(p.w);
    const glm::dmat3 rotation = base * glm::dmat3(glm::dvec3(ca, 0.0, sa), glm::dvec3(0.0, 1.0, 0.0), glm::dvec3(-sa, 0.0, ca));
    const double a = std::exp(p.x), b = p.y * a, c = std::exp(p.z);
    const glm::dmat3 s_inv(glm::dvec3(1.0 / a, 0.0, 0.0), glm::dvec3(0.0, 1.0 / c, 0.0), glm::dvec3(-b / a, 0.0, 1.0));
    const glm::dmat3 mi = s_inv * glm::transpose(rotation);
    // glm indexes [column][row].
    return glm::dvec4(mi[0][0], mi[2][0], mi[1][1], mi[0][2]) / mi[2][2];
}

// The parameters of a given M^-1 under this rotation (the part of it that S can express).
bool params_of(const glm::dmat3& rotation, const glm::dvec4& m_inv, glm::dvec4& p) {
    const glm::dmat3 mi = m_inv_matrix(m_inv);
    if (!(std::abs(glm::determinant(mi)) > 0.0)) return false;
    glm::dmat3 s = glm::transpose(rotation) * glm::inverse(mi);
    if (!(std::abs(s[2][2]) > 0.0)) return false;
    s /= s[2][2];
    const double a = s[0][0], b = s[2][0], c = s[1][1];
    if (!(a > 0.0) || !(c > 0.0)) return false;
    p = glm::dvec4(std::log(a), b / a, std::log(c), 0.0);
    return true;
}

template <class Vec, class F>
Vec nelder_mead(F&& f, Vec start, double step, int max_iter) {
    constexpr int n = Vec::length();
    std::array<Vec, n + 1> x;
    std::array<double, n + 1> fx;
    x[0] = start;
    for (int i = 0; i < n; ++i) {
        x[i + 1] = start;
        x[i + 1][i] += step;
    }
    for (int i = 0; i <= n; ++i) fx[i] = f(x[i]);
    for (int iter = 0; iter < max_iter; ++iter) {
        std::array<int, n + 1> order;
        for (int i = 0; i <= n; ++i) order[i] = i;
        std::sort(order.begin(), order.end(), [&](int a, int b) { return fx[a] < fx[b]; });
        const int best = order[0], worst = order[n], second = order[n - 1];
        double size = 0.0;
        for (int i = 1; i <= n; ++i) size = std::max(size, glm::length(x[order[i]] - x[best]));
        if (size < 1e-6 || fx[worst] - fx[best] <= 1e-9 * std::abs(fx[best])) break;
        Vec centroid(0.0);
        for (int i = 0; i < n; ++i) centroid += x[order[i]];
        centroid /= double(n);
        const Vec xr = centroid + (centroid - x[worst]);
        const double fr = f(xr);
        if (fr < fx[best]) {
            const Vec xe = centroid + 2.0 * (centroid - x[worst]);
            const double fe = f(xe);
            if (fe < fr) x[worst] = xe, fx[worst] = fe;
            else x[worst] = xr, fx[worst] = fr;
        } else if (fr < fx[second]) {
            x[worst] = xr, fx[worst] = fr;
        } else {
            const bool outside = fr < fx[worst];
            const Vec xc = outside ? centroid + 0.5 * (xr - centroid) : centroid + 0.5 * (x[worst] - centroid);
            const double fc = f(xc);
            if (fc < (outside ? fr : fx[worst])) {
                x[worst] = xc, fx[worst] = fc;
            } else {
                for (int i = 0; i <= n; ++i)
                    if (i != best) x[i] = x[best] + 0.5 * (x[i] - x[best]), fx[i] = f(x[i]);
            }
        }
    }
    int best = 0;
    for (int i = 1; i <= n; ++i)
        if (fx[i] < fx[best]) best = i;
    return x[best];
}

}  // namespace

float table_roughness(int i) { return float(i) / float(kTableSize - 1); }

float table_cos_theta(int j) {
    const double t = double(j) / double(kTableSize - 1);
    const double u = std::sqrt(0.25 + 2.0 * t) - 0.5;
    return std::max(float(std::cos(u * 0.5 * kPi)), kMinCos);
}

double brdf_cos(float roughness, glm::vec3 v, glm::vec3 l) {
    if (l.z <= 0.0f || v.z <= 0.0f) return 0.0;  // brdf.glsl's test, on its float inputs
    return lobe_cos(alpha_of(roughness), glm::dvec3(v), glm::dvec3(l));
}

float ltc_eval(const glm::vec4& m_inv, glm::vec3 w) {
    const glm::dmat3 mi = m_inv_matrix(glm::dvec4(m_inv));
    return float(ltc_value(mi, std::abs(glm::determinant(mi)), glm::normalize(glm::dvec3(w))));
}

Fit fit_entry(float roughness, float cos_theta, const Fit* initial_guess) {
    Lobe lobe;
    lobe.roughness = roughness;
    lobe.alpha = alpha_of(roughness);
    const double ct = std::clamp(double(cos_theta), double(kMinCos), 1.0);
    lobe.v = glm::dvec3(std::sqrt(1.0 - ct * ct), 0.0, ct);
    integrate_lobe(lobe);

    Fit fit{};
    fit.norm = float(lobe.norm);
    fit.fresnel = float(lobe.fresnel);
    if (!(lobe.norm > 0.0)) {
        fit.m_inv = glm::vec4(1, 0, 1, 0);
        return fit;
    }
    const Samples samples = make_samples(lobe, kFitGrid);
    const glm::dmat3 rotation = axis_rotation(lobe.average);
    auto l1 = [&](const glm::dvec4& p) { return distance(lobe, samples, m_inv_of(rotation, p), 1.0); };
    auto optimise = [&](glm::dvec4 start, double norm_power) {
        auto objective = [&](const glm::dvec4& p) { return distance(lobe, samples, m_inv_of(rotation, p), norm_power); };
        start = nelder_mead(objective, start, 0.05, 500);
        return nelder_mead(objective, start, 0.01, 300);  // restart: a collapsed simplex stops early
    };

    // Two starts: a cosine of the lobe's width (alpha) on the average direction, and the
    // neighbour's fit; the result with the smaller L1 distance wins (an Lp norm with large p would
    // prefer a wide LTC away from a sharp lobe to a slightly misplaced narrow one).
    const glm::dvec4 isotropic(std::log(lobe.alpha), 0.0, std::log(lobe.alpha), 0.0);
    glm::dvec4 guess;
    const bool has_guess = initial_guess && params_of(rotation, glm::dvec4(initial_guess->m_inv), guess);
    glm::dvec4 p = optimise(isotropic, kFitPower);
    double best = l1(p);
    auto consider = [&](const glm::dvec4& q) {
        const double e = l1(q);
        if (e < best) p = q, best = e;
    };
    if (has_guess) consider(optimise(guess, kFitPower));
    // Where that fit is poor (only the sharp lobes at NdotV ~ 0, the last row) the p = 1.5 minimum
    // can lie off the lobe altogether (L1 1.98, disjoint, at r = 0.03): try the paper's L3 too.
    if (best > 0.5) {
        consider(optimise(isotropic, 3.0));
        if (has_guess) consider(optimise(guess, 3.0));
    }
    fit.m_inv = glm::vec4(m_inv_of(rotation, p));
    const Samples check = make_samples(lobe, kErrorGrid);
    fit.error = float(distance(lobe, check, glm::dvec4(fit.m_inv), 1.0));
    return fit;
}

std::vector<Fit> fit_table() {
    constexpr int N = kTableSize;
    std::vector<Fit> table(N * N);
    // Normal incidence, from rough to smooth, each seeded from the rougher one; then each
    // roughness's row of view angles seeded from the previous angle. Rows are independent, so
    // they run on the machine's cores; the result does not depend on the thread count.
    for (int i = N - 1; i >= 0; --i)
        table[i] = fit_entry(table_roughness(i), table_cos_theta(0), i == N - 1 ? nullptr : &table[i + 1]);
    const unsigned threads = std::max(1u, std::min(std::thread::hardware_concurrency(), 8u));
    std::vector<std::thread> pool;
    for (unsigned t = 0; t < threads; ++t)
        pool.emplace_back([&, t] {
            for (int i = int(t); i < N; i += int(threads))
                for (int j = 1; j < N; ++j)
                    table[j * N + i] = fit_entry(table_roughness(i), table_cos_theta(j), &table[(j - 1) * N + i]);
        });
    for (std::thread& th : pool) th.join();
    return table;
}

}  // namespace candela::ltc
