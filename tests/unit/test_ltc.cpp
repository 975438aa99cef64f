// The LTC table (engine/effects/area_lights/ltc_table.inc, written by samples/ltc_fit) against
// Candela's specular BRDF: its amplitude is the lobe's directional albedo, its distributions are
// normalised and put the lobe's mass where the lobe has it, and it is what the fit gives today.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <vector>

#include "effects/area_lights/ltc.hpp"
#include "rt/sampling.hpp"

namespace candela::ltc {
namespace {

#include "effects/area_lights/ltc_table.inc"

constexpr int N = kTableSize;
constexpr double kPi = 3.14159265358979323846;

glm::vec4 table_m_inv(int i, int j) {
    const float* m = kLtcMatrix[j * N + i];
    return {m[0], m[1], m[2], m[3]};
}

glm::vec3 view(float cos_theta) { return {std::sqrt(std::max(0.0f, 1.0f - cos_theta * cos_theta)), 0.0f, cos_theta}; }

// Estimate of integrals of the lobe D * V * NdotL (times g(l)) over the hemisphere: GGX
// visible-normal sampling (engine/rt/sampling.hpp, Heitz 2018), one jittered sample per cell of
// an n x n grid (the library's quadrature takes the cell midpoints), weight = brdf_cos / pdf with
// pdf = G1(v) D / (4 NdotV) computed here.
template <class G>
double vndf_integral(float roughness, float cos_theta, int n, G&& g) {
    std::uint32_t seed = 0x9e3779b9u ^ std::uint32_t(roughness * 1e6f) ^ (std::uint32_t(cos_theta * 1e6f) << 7);
    auto rnd = [&seed] {
        seed = rt::pcg_hash(seed);
        return float(seed >> 8) * (1.0f / 16777216.0f);
    };
    const float alpha = std::max(roughness * roughness, 1e-3f);
    const glm::vec3 v = view(cos_theta);
    const double a2 = double(alpha) * alpha;
    double sum = 0.0;
    for (int a = 0; a < n; ++a)
        for (int b = 0; b < n; ++b) {
            const glm::vec3 h = rt::sample_ggx_vndf(v, alpha, {(a + rnd()) / n, (b + rnd()) / n});
            const glm::vec3 l = glm::normalize(2.0f * glm::dot(v, h) * h - v);
            if (l.z <= 0.0f) continue;
            const glm::dvec3 hd = glm::normalize(glm::dvec3(l) + glm::dvec3(v));
            const double d = hd.z * hd.z * (a2 - 1.0) + 1.0;
            const double D = a2 / (kPi * d * d);
            const double g1 = 2.0 * v.z / (v.z + std::sqrt(a2 + (1.0 - a2) * v.z * v.z));
            const double pdf = g1 * D / (4.0 * v.z);
            sum += brdf_cos(roughness, v, l) / pdf * g(l);
        }
    return sum / (double(n) * n);
}

// Integral of the LTC times g over the sphere by a quadrature of its own: polar coordinates
// around the LTC's peak direction with the polar angle psi = 2 atan(k t / (1 - t)), t uniform,
// which packs the points within ~k of the peak (k: the lobe's angular size).
template <class G>
double ltc_integral(const glm::vec4& m_inv, int nt, int nphi, G&& g) {
    const glm::mat3 mi(glm::vec3(m_inv.x, 0, m_inv.w), glm::vec3(0, m_inv.z, 0), glm::vec3(m_inv.y, 0, 1));
    const glm::dmat3 m = glm::inverse(glm::dmat3(mi));
    const glm::dvec3 axis = glm::normalize(m * glm::dvec3(0, 0, 1));
    const double wx = std::acos(std::clamp(glm::dot(axis, glm::normalize(m * glm::dvec3(0.5, 0, 1))), -1.0, 1.0));
    const double wy = std::acos(std::clamp(glm::dot(axis, glm::normalize(m * glm::dvec3(0, 0.5, 1))), -1.0, 1.0));
    const double k = std::tan(0.5 * std::clamp(std::min(wx, wy), 1e-5, 1.0));
    glm::dvec3 t1, t2;
    {
        glm::vec3 a, b;
        rt::onb(glm::vec3(axis), a, b);
        t1 = glm::dvec3(a), t2 = glm::dvec3(b);
    }
    double sum = 0.0;
    for (int it = 0; it < nt; ++it) {
        const double t = (it + 0.5) / nt;
        const double s = k * t / (1.0 - t);
        const double psi = 2.0 * std::atan(s);
        const double dpsi = 2.0 * k / ((1.0 - t) * (1.0 - t) + k * k * t * t) / nt;
        for (int ip = 0; ip < nphi; ++ip) {
            const double phi = 2.0 * kPi * (ip + 0.5) / nphi;
            const glm::dvec3 w = std::cos(psi) * axis + std::sin(psi) * (std::cos(phi) * t1 + std::sin(phi) * t2);
            sum += ltc_eval(m_inv, glm::vec3(w)) * g(w) * std::sin(psi) * dpsi * (2.0 * kPi / nphi);
        }
    }
    return sum;
}

TEST(Ltc, AmplitudeIsTheDirectionalAlbedoOfTheBrdf) {
    // Norm and Fresnel moment of every view angle at every other roughness (and r = 1) against
    // the jittered VNDF estimate (256 x 256). Measured: worst |diff| 3.7e-4 for the norm, 8.1e-5
    // for the Fresnel moment (the estimate's own error is ~2e-4); bound 1e-3 absolute.
    double worst_norm = 0.0, worst_fresnel = 0.0;
    int worst_at = 0;
    for (int j = 0; j < N; ++j)
        for (int i = 0; i < N; i = i + 2 == N ? N - 1 : i + 2) {
            const float r = table_roughness(i), c = table_cos_theta(j);
            const double norm = vndf_integral(r, c, 256, [](const glm::vec3&) { return 1.0; });
            const glm::vec3 v = view(c);
            const double fresnel = vndf_integral(r, c, 256, [&](const glm::vec3& l) {
                const double vh = glm::dot(glm::dvec3(v), glm::normalize(glm::dvec3(v) + glm::dvec3(l)));
                return std::pow(1.0 - std::clamp(vh, 0.0, 1.0), 5.0);
            });
            const double dn = std::abs(norm - kLtcAmplitude[j * N + i][0]);
            if (dn > worst_norm) worst_norm = dn, worst_at = j * N + i;
            worst_fresnel = std::max(worst_fresnel, std::abs(fresnel - kLtcAmplitude[j * N + i][1]));
            // The albedo of a passive lobe cannot exceed 1 (with F = 1, up to quadrature error).
            EXPECT_LE(kLtcAmplitude[j * N + i][0], 1.0 + 1e-3) << "r " << r << " NdotV " << c;
        }
    std::printf("norm: worst |table - VNDF estimate| %.3g (entry %d), fresnel: %.3g\n", worst_norm, worst_at, worst_fresnel);
    EXPECT_LT(worst_norm, 1e-3);
    EXPECT_LT(worst_fresnel, 1e-3);
}

TEST(Ltc, FittedDistributionsIntegrateToOne) {
    // ltc_eval's normalisation (|det M^-1| / |M^-1 w|^3) against a quadrature of the sphere. Rows
    // up to j = 24 (NdotV >= 0.25): beyond, the sharp lobes are stretched 100:1 and more, which
    // this polar grid does not resolve.
    double worst = 0.0;
    for (int j = 0; j <= 24; j += 2)
        for (int i = 0; i < N; i += 3) {
            const double total = ltc_integral(table_m_inv(i, j), 1024, 512, [](const glm::dvec3&) { return 1.0; });
            worst = std::max(worst, std::abs(total - 1.0));
            EXPECT_NEAR(total, 1.0, 1e-3) << "i " << i << " j " << j;
        }
    std::printf("LTC integral over the sphere: worst |1 - integral| %.3g\n", worst);
}

TEST(Ltc, FittedLobePutsTheMassWhereTheBrdfHasIt) {
    // Integrals of the normalised lobe f / norm (VNDF estimate) and of the LTC (own quadrature)
    // over spherical caps around the lobe's mirror direction, of radius a few times the lobe's
    // width, and over caps beside it; only the upper hemisphere counts (a shader clips polygons at
    // the horizon). Bound per entry: about 1.5-5x the measured worst difference (printed), from
    // 3e-4 for sharp lobes to 0.049 for r = 0.52 at 66 degrees, where the LTC shape fits worst.
    struct Case {
        int i, j;
        double bound;
    };
    const Case cases[] = {{2, 0, 0.005}, {6, 10, 0.005}, {12, 16, 0.02}, {16, 0, 0.025}, {16, 20, 0.07}, {24, 8, 0.01}, {31, 16, 0.005}};
    for (const Case& cs : cases) {
        const float r = table_roughness(cs.i), c = table_cos_theta(cs.j);
        const float alpha = std::max(r * r, 1e-3f);
        const glm::vec4 m = table_m_inv(cs.i, cs.j);
        const double norm = kLtcAmplitude[cs.j * N + cs.i][0];
        const glm::dvec3 mirror(-std::sqrt(1.0 - double(c) * c), 0.0, c);
        double worst = 0.0;
        for (const double radius_scale : {1.0, 2.0, 4.0})
            for (const double offset : {0.0, 1.0}) {
                const double radius = std::min(1.5, radius_scale * 2.0 * alpha + 0.01);
                // Offset caps sit beside the mirror direction, turned about the normal.
                const double az = offset * radius;
                const glm::dvec3 centre = glm::normalize(glm::dvec3(mirror.x * std::cos(az), mirror.x * std::sin(az), mirror.z));
                auto in_cap = [&](const glm::dvec3& w) { return w.z > 0.0 && glm::dot(w, centre) > std::cos(radius) ? 1.0 : 0.0; };
                const double brdf = vndf_integral(r, c, 512, [&](const glm::vec3& l) { return in_cap(glm::dvec3(l)); }) / norm;
                const double ltc = ltc_integral(m, 1024, 1024, in_cap);
                worst = std::max(worst, std::abs(brdf - ltc));
                EXPECT_NEAR(ltc, brdf, cs.bound) << "r " << r << " NdotV " << c << " cap radius " << radius << " offset " << offset;
            }
        std::printf("r %.3f NdotV %.3f: worst cap |lobe - LTC| %.4f (bound %.3f)\n", r, c, worst, cs.bound);
    }
}

TEST(Ltc, TableInTheTreeIsTheFitOfTheCurrentBrdf) {
    // A BRDF change not followed by `ltc_fit` fails here: re-fit a few entries, seeded like the
    // table's own fit (previous view angle, or the next rougher entry at normal incidence).
    const int entries[][2] = {{31, 0}, {20, 5}, {8, 12}, {3, 22}, {14, 29}};
    for (const auto& e : entries) {
        const int i = e[0], j = e[1];
        const float* seed_row = j > 0 ? kLtcMatrix[(j - 1) * N + i] : (i < N - 1 ? kLtcMatrix[i + 1] : nullptr);
        Fit seed{};
        if (seed_row) seed.m_inv = {seed_row[0], seed_row[1], seed_row[2], seed_row[3]};
        const Fit fit = fit_entry(table_roughness(i), table_cos_theta(j), seed_row ? &seed : nullptr);
        const glm::vec4 m = table_m_inv(i, j);
        const float scale = std::max({std::abs(m.x), std::abs(m.z), 1.0f});
        for (int k = 0; k < 4; ++k) EXPECT_NEAR(fit.m_inv[k], m[k], 1e-3f * scale) << "i " << i << " j " << j << " k " << k;
        EXPECT_NEAR(fit.norm, kLtcAmplitude[j * N + i][0], 1e-6f) << "i " << i << " j " << j;
        EXPECT_NEAR(fit.fresnel, kLtcAmplitude[j * N + i][1], 1e-6f) << "i " << i << " j " << j;
    }
}

TEST(Ltc, TableCoordsHitTexelCentres) {
    for (int j = 0; j < N - 1; ++j)  // the last row is fitted at NdotV = 1e-4, not 0
        for (int i = 0; i < N; i += 7) {
            const glm::vec2 uv = table_coords(table_roughness(i), table_cos_theta(j));
            EXPECT_NEAR(uv.x, (i + 0.5f) / N, 1e-5f);
            EXPECT_NEAR(uv.y, (j + 0.5f) / N, 1e-4f) << j;
        }
    const glm::vec2 grazing = table_coords(1.0f, 0.0f);
    EXPECT_NEAR(grazing.y, (N - 0.5f) / N, 1e-6f);
}

}  // namespace
}  // namespace candela::ltc
