// The ray tracer's math on the CPU (C++ twins of the GLSL): watertight triangles, robust
// spheres, ray offsets, and the samplers' pdfs.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "rt/intersect.hpp"
#include "rt/sampling.hpp"

namespace candela::rt {
namespace {

// An octahedron (closed, 8 triangles, shared edges and vertices), wound outwards.
std::vector<std::array<glm::vec3, 3>> octahedron(float scale, glm::vec3 center) {
    const glm::vec3 v[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    const int f[8][3] = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
    std::vector<std::array<glm::vec3, 3>> tris;
    for (const auto& face : f) tris.push_back({center + v[face[0]] * scale, center + v[face[1]] * scale, center + v[face[2]] * scale});
    return tris;
}

int count_hits(const std::vector<std::array<glm::vec3, 3>>& tris, const Ray& ray) {
    const WatertightRay w = watertight_setup(ray);
    int hits = 0;
    for (const auto& t : tris) {
        glm::vec2 bary;
        hits += intersect_triangle(w, t[0], t[1], t[2], 1e30f, bary) > 0.0f;
    }
    return hits;
}

TEST(Watertight, RaysThroughEveryVertexAndEdgeOfAClosedMeshHit) {
    // From inside, rays aimed exactly at vertices, edge midpoints and edge points must hit at
    // least one triangle (a leak would be zero hits), at several scales and far from the origin.
    for (const float scale : {1e-3f, 1.0f, 1e3f})
        for (const glm::vec3 center : {glm::vec3(0.0f), glm::vec3(1e4f, -3e3f, 2e4f)}) {
            // A mesh 1e-3 across at 2e4 is below float precision (one ulp there is ~2e-3):
            // its vertices collapse, there is no closed surface left to test.
            if (scale < 1e-6f * glm::length(center)) continue;
            const auto tris = octahedron(scale, center);
            std::mt19937 rng(7);
            std::uniform_real_distribution<float> u(0.0f, 1.0f);
            int rays = 0;
            for (const auto& t : tris)
                for (int e = 0; e < 3; ++e) {
                    const glm::vec3 a = t[static_cast<size_t>(e)], b = t[static_cast<size_t>((e + 1) % 3)];
                    for (float s : {0.0f, 0.5f, u(rng), u(rng), u(rng)}) {
                        const glm::vec3 target = a + (b - a) * s;
                        const glm::vec3 origin = center + glm::vec3(0.01f, -0.02f, 0.015f) * scale;
                        EXPECT_GE(count_hits(tris, {origin, target - origin}), 1)
                            << "scale " << scale << " leak at edge point " << s;
                        ++rays;
                    }
                }
            EXPECT_EQ(rays, 8 * 3 * 5);
        }
}

TEST(Watertight, SharedEdgeOfTwoTrianglesIsNeverMissed) {
    const glm::vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0), d(1, 1, 0);
    const std::vector<std::array<glm::vec3, 3>> quad = {{a, b, d}, {a, d, c}};
    // Rays straight down onto the diagonal a-d, from many directions.
    for (int i = 0; i <= 100; ++i) {
        const float s = static_cast<float>(i) / 100.0f;
        const glm::vec3 p = a + (d - a) * s;
        for (const glm::vec3 dir : {glm::vec3(0, 0, -1), glm::vec3(0.3f, -0.2f, -1), glm::vec3(-0.7f, 0.1f, -0.2f)})
            EXPECT_GE(count_hits(quad, {p - dir * 3.0f, dir}), 1) << s;
    }
}

TEST(Watertight, GrazingAndParallelRaysDoNotProduceNan) {
    const glm::vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
    glm::vec2 bary;
    const WatertightRay parallel = watertight_setup({{-1, 0.25f, 0}, {1, 0, 0}});
    const float t = intersect_triangle(parallel, a, b, c, 1e30f, bary);
    EXPECT_FALSE(std::isnan(t));
    EXPECT_LE(t, 0.0f);  // in-plane: no hit
    const WatertightRay grazing = watertight_setup({{-1, 0.25f, 1e-6f}, {1, 0, -1e-6f}});
    const float tg = intersect_triangle(grazing, a, b, c, 1e30f, bary);
    EXPECT_TRUE(tg < 0.0f || std::isfinite(tg));
    // The hit point of a regular hit is where it should be.
    const WatertightRay down = watertight_setup({{0.25f, 0.25f, 2.0f}, {0, 0, -1}});
    EXPECT_FLOAT_EQ(intersect_triangle(down, a, b, c, 1e30f, bary), 2.0f);
    EXPECT_FLOAT_EQ(bary.x, 0.25f);
    EXPECT_FLOAT_EQ(bary.y, 0.25f);
    // tmax is respected.
    EXPECT_LT(intersect_triangle(down, a, b, c, 1.5f, bary), 0.0f);
}

TEST(Sphere, UnitSphereFarAwayIsHitAccurately) {
    const glm::vec3 center(0.0f, 0.0f, -1e5f);
    const float t = intersect_sphere({{0, 0, 0}, {0, 0, -1}}, center, 1.0f, 0.0f, 1e30f);
    EXPECT_NEAR(t, 1e5f - 1.0f, 1e5f * 1e-6f);
    // Just inside the silhouette still hits, just outside misses.
    EXPECT_GT(intersect_sphere({{0.999f, 0, 0}, {0, 0, -1}}, center, 1.0f, 0.0f, 1e30f), 0.0f);
    EXPECT_LT(intersect_sphere({{1.001f, 0, 0}, {0, 0, -1}}, center, 1.0f, 0.0f, 1e30f), 0.0f);
}

TEST(Sphere, TinySphereIsHit) {
    const float r = 1e-4f;
    const float t = intersect_sphere({{0, 0, 1}, {0, 0, -1}}, glm::vec3(0.0f), r, 0.0f, 1e30f);
    EXPECT_NEAR(t, 1.0f - r, 1e-7f);
    EXPECT_GT(intersect_sphere({{0.9e-4f, 0, 1}, {0, 0, -1}}, glm::vec3(0.0f), r, 0.0f, 1e30f), 0.0f);
    EXPECT_LT(intersect_sphere({{1.1e-4f, 0, 1}, {0, 0, -1}}, glm::vec3(0.0f), r, 0.0f, 1e30f), 0.0f);
}

TEST(Sphere, OriginInsideAndTangentRays) {
    // From inside, the exit point.
    EXPECT_NEAR(intersect_sphere({{0.5f, 0, 0}, {1, 0, 0}}, glm::vec3(0.0f), 2.0f, 0.0f, 1e30f), 1.5f, 1e-6f);
    // A tangent ray: a hit at the touching point or a miss, never NaN.
    const float t = intersect_sphere({{1.0f, 0, 5}, {0, 0, -1}}, glm::vec3(0.0f), 1.0f, 0.0f, 1e30f);
    EXPECT_FALSE(std::isnan(t));
    if (t > 0.0f) EXPECT_NEAR(t, 5.0f, 1e-3f);
    // Unnormalised directions give t along the direction as given.
    EXPECT_NEAR(intersect_sphere({{0, 0, 5}, {0, 0, -2}}, glm::vec3(0.0f), 1.0f, 0.0f, 1e30f), 2.0f, 1e-6f);
}

TEST(OffsetRay, LeavesTheSurfaceAtAnyScale) {
    const glm::vec3 n(0, 0, 1);
    const float min_offset = ray_offset_for_extent(8.0f);
    EXPECT_FLOAT_EQ(min_offset, 1.0f / 65536.0f);  // Wächter & Binder's constant for a unit-size scene
    for (const float z : {0.0f, 1e-5f, 1.0f, 1e3f, 1e5f, -1e5f}) {
        const glm::vec3 p(0.3f, -0.2f, z);
        const glm::vec3 o = offset_ray(p, n, min_offset);
        EXPECT_GT(o.z, p.z) << z;                            // moved to the normal's side
        EXPECT_LT(o.z - p.z, std::max(1e-4f, std::fabs(z) * 1e-4f)) << z;  // by a few ulps only
        // A ray leaving along the surface's tangent from the offset point does not hit the plane.
        const WatertightRay w = watertight_setup({o, glm::vec3(1, 0, 0.001f)});
        glm::vec2 bary;
        const glm::vec3 a(-1e6f, -1e6f, z), b(1e6f, -1e6f, z), c(0, 1e6f, z);
        EXPECT_LT(intersect_triangle(w, a, b, c, 1e30f, bary), 0.0f) << z;
    }
}

TEST(Sampling, CosineHemisphereMatchesItsPdf) {
    // Histogram of cos(theta) in 10 bins against the integral of the pdf over each bin.
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    const int n = 200000, bins = 10;
    std::vector<int> hist(bins, 0);
    for (int i = 0; i < n; ++i) {
        const glm::vec3 d = sample_cosine_hemisphere({u(rng), u(rng)});
        EXPECT_NEAR(glm::length(d), 1.0f, 1e-5f);
        hist[static_cast<size_t>(std::min(bins - 1, static_cast<int>(d.z * bins)))]++;
    }
    double chi2 = 0.0;
    for (int b = 0; b < bins; ++b) {
        // P(cos in [c0, c1]) = c1^2 - c0^2 for pdf cos/pi.
        const double c0 = static_cast<double>(b) / bins, c1 = static_cast<double>(b + 1) / bins;
        const double expected = n * (c1 * c1 - c0 * c0);
        chi2 += (hist[static_cast<size_t>(b)] - expected) * (hist[static_cast<size_t>(b)] - expected) / expected;
    }
    EXPECT_LT(chi2, 27.9);  // chi-square, 9 degrees of freedom, p = 0.001
}

// Numerical integral of a pdf over the sphere (midpoint rule in theta, phi).
template <typename Pdf>
double integrate_sphere(Pdf pdf) {
    const int nt = 400, np = 400;
    double sum = 0.0;
    for (int i = 0; i < nt; ++i) {
        const double theta = (i + 0.5) * kPi / nt;
        for (int j = 0; j < np; ++j) {
            const double phi = (j + 0.5) * 2.0 * kPi / np;
            const glm::vec3 l(static_cast<float>(std::sin(theta) * std::cos(phi)), static_cast<float>(std::sin(theta) * std::sin(phi)),
                              static_cast<float>(std::cos(theta)));
            sum += pdf(l) * std::sin(theta) * (kPi / nt) * (2.0 * kPi / np);
        }
    }
    return sum;
}

TEST(Sampling, PdfsIntegrateToOne) {
    EXPECT_NEAR(integrate_sphere([](const glm::vec3& l) { return pdf_cosine_hemisphere(l.z); }), 1.0, 1e-3);
    for (const float alpha : {0.2f, 0.5f, 1.0f})
        for (const float view_z : {1.0f, 0.5f, 0.1f}) {
            const glm::vec3 v = glm::normalize(glm::vec3(std::sqrt(1.0f - view_z * view_z), 0.0f, view_z));
            const double total = integrate_sphere([&](const glm::vec3& l) {
                const glm::vec3 h = glm::normalize(v + l);
                if (h.z <= 0.0f || glm::dot(v, h) <= 0.0f) return 0.0f;
                return pdf_ggx_vndf_reflection(v.z, h.z, alpha);
            });
            EXPECT_NEAR(total, 1.0, 0.02) << "alpha " << alpha << " view_z " << view_z;
        }
}

TEST(Sampling, GgxVndfSamplesFollowTheirPdf) {
    // E[h(l) / pdf(l)] over VNDF samples equals the integral of h over where samples land:
    // with h = cos(theta_l) / pi (integral 1 over the upper hemisphere).
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (const float alpha : {0.1f, 0.5f, 1.0f})
        for (const float view_z : {0.9f, 0.4f}) {
            const glm::vec3 v = glm::normalize(glm::vec3(std::sqrt(1.0f - view_z * view_z), 0.0f, view_z));
            const int n = 200000;
            double sum = 0.0;
            for (int i = 0; i < n; ++i) {
                const glm::vec3 h = sample_ggx_vndf(v, alpha, {u(rng), u(rng)});
                const glm::vec3 l = glm::reflect(-v, h);
                if (l.z <= 0.0f) continue;
                const float pdf = pdf_ggx_vndf_reflection(v.z, h.z, alpha);
                sum += (l.z / kPi) / pdf;
            }
            EXPECT_NEAR(sum / n, 1.0, 0.02) << "alpha " << alpha << " view_z " << view_z;
        }
}

TEST(Sampling, OrthonormalBasis) {
    for (const glm::vec3 n : {glm::vec3(0, 0, 1), glm::vec3(0, 0, -1), glm::normalize(glm::vec3(1, 2, 3)),
                              glm::normalize(glm::vec3(0.0f, -1e-7f, -1.0f))}) {
        glm::vec3 t, b;
        onb(n, t, b);
        EXPECT_NEAR(glm::dot(t, n), 0.0f, 1e-6f);
        EXPECT_NEAR(glm::dot(b, n), 0.0f, 1e-6f);
        EXPECT_NEAR(glm::dot(t, b), 0.0f, 1e-6f);
        EXPECT_NEAR(glm::length(t), 1.0f, 1e-5f);
    }
}

}  // namespace
}  // namespace candela::rt
