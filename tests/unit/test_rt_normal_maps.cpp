// The tracer's shading normals: a white furnace with normal maps. A white metal sphere
// (base colour 1, metallic 1) with a strong bumpy normal map, alone in a constant environment of
// radiance 1 with no lights, under `path`, `whitted` and the raster.
//
// What the answer must be: the sphere mesh is convex, so every ray that leaves it above its
// geometric surface escapes to the environment. A pixel then averages, over its footprint, the
// single-scattering albedo E(ns.v) of the GGX lobe about the shading normal (the BRDF of
// shaders/common/brdf.glsl loses the energy of multiple scattering; with base colour 1 the
// Fresnel term is 1). So every pixel lies in [E_min, 1], where E_min is the smallest albedo over
// all n.v of that roughness, measured below by quadrature over the visible normals. Each traced
// sample is itself in [0, 1] here (VNDF weights G2/G1 <= 1), so the upper bound is exact.
// The bug this guards against (shading normals that bend the reflected ray below the geometric
// surface) gave rings of pixels near 0.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "gl_fixture.hpp"
#include "gltf_builder.hpp"
#include "image/image.hpp"
#include "render/still.hpp"
#include "rt/ray_tracer.hpp"
#include "rt/sampling.hpp"
#include "scene/gltf_loader.hpp"

namespace candela {
namespace {
namespace fs = std::filesystem;
using nlohmann::json;

// Single-scattering directional albedo of a white GGX metal (F = 1) at n.v = mu: the mean VNDF
// sampling weight G2 / G1 (Heitz 2018, "Sampling the GGX Distribution of Visible Normals"),
// with the height-correlated G2 of brdf.glsl, by an n x n stratified quadrature.
double ggx_white_albedo(double mu, float alpha, int n = 256) {
    const glm::vec3 v(static_cast<float>(std::sqrt(std::max(0.0, 1.0 - mu * mu))), 0.0f, static_cast<float>(mu));
    const double a2 = static_cast<double>(alpha) * alpha;
    const auto lambda_term = [&](double c) { return std::sqrt(c * c * (1.0 - a2) + a2); };
    double sum = 0.0;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            const glm::vec2 u((static_cast<float>(i) + 0.5f) / static_cast<float>(n), (static_cast<float>(j) + 0.5f) / static_cast<float>(n));
            const glm::vec3 h = rt::sample_ggx_vndf(v, alpha, u);
            const glm::vec3 l = 2.0f * glm::dot(v, h) * h - v;
            if (l.z <= 0.0f) continue;
            const double nl = l.z, nv = mu;
            // G2 / G1 with G2 = 4 V nl nv, V = 0.5 / (nl L(nv) + nv L(nl)) (brdf.glsl).
            const double g2 = 2.0 * nl * nv / (nl * lambda_term(nv) + nv * lambda_term(nl));
            sum += g2 / rt::smith_g1_ggx(static_cast<float>(nv), alpha);
        }
    return sum / (static_cast<double>(n) * n);
}
// The smallest albedo over n.v in [1e-4, 1] (the raster and the tracer bend n.v up to 1e-4): a
// smooth lobe dips near n.v ~ alpha (0.89 at roughness 0.05), a rough one near n.v ~ 0.5, so
// the n.v are spaced logarithmically.
double ggx_white_albedo_min(float alpha) {
    double lo = 1.0;
    for (int k = 0; k <= 160; ++k) lo = std::min(lo, ggx_white_albedo(std::pow(10.0, -4.0 + 4.0 * k / 160.0), alpha));
    return lo;
}

// A tangent-space normal map of bumps, h = sin(2 pi 12 u) sin(2 pi 6 v) (about square bumps on a
// UV sphere), tilted up to 60 degrees from the surface normal.
void write_bumpy_normal_map(const fs::path& path, int w, int h) {
    std::vector<unsigned char> rgba(static_cast<size_t>(w) * h * 4);
    const double tpi = 6.283185307179586, k = std::tan(60.0 * 3.141592653589793 / 180.0);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const double u = (x + 0.5) / w, v = (y + 0.5) / h;
            const double gx = std::cos(tpi * 12 * u) * std::sin(tpi * 6 * v);
            const double gy = std::sin(tpi * 12 * u) * std::cos(tpi * 6 * v);
            glm::dvec3 n(-k * gx, -k * gy, 1.0);
            n = glm::normalize(n);
            unsigned char* p = &rgba[(static_cast<size_t>(y) * w + x) * 4];
            for (int c = 0; c < 3; ++c) p[c] = static_cast<unsigned char>(std::lround((n[c] * 0.5 + 0.5) * 255.0));
            p[3] = 255;
        }
    write_display_rgba8(path, rgba, w, h);
}

// A UV sphere of radius 1 with TEXCOORD_0 (u around, v down from the north pole) and outward
// normals; the loader generates the tangents. Seam vertices are duplicated for the UVs, the
// degenerate triangles at the poles are left out.
int add_uv_sphere(test::GltfBuilder& b, int material, int rings = 32, int segments = 64) {
    std::vector<glm::vec3> p;
    std::vector<glm::vec2> uv;
    std::vector<uint32_t> idx;
    for (int i = 0; i <= rings; ++i)
        for (int j = 0; j <= segments; ++j) {
            const double t = 3.14159265358979 * i / rings, ph = 2.0 * 3.14159265358979 * j / segments;
            p.emplace_back(std::sin(t) * std::cos(ph), std::cos(t), -std::sin(t) * std::sin(ph));
            uv.emplace_back(static_cast<float>(j) / segments, static_cast<float>(i) / rings);
        }
    const auto at = [&](int i, int j) { return static_cast<uint32_t>(i * (segments + 1) + j); };
    for (int i = 0; i < rings; ++i)
        for (int j = 0; j < segments; ++j) {
            if (i != 0) idx.insert(idx.end(), {at(i, j), at(i + 1, j), at(i, j + 1)});
            if (i != rings - 1) idx.insert(idx.end(), {at(i, j + 1), at(i + 1, j), at(i + 1, j + 1)});
        }
    return b.add_mesh({{"POSITION", b.add_positions(p)}, {"NORMAL", b.add_vec3(p)}, {"TEXCOORD_0", b.add_vec2(uv)}},
                      b.add_indices(idx), material);
}

constexpr float kCameraDistance = 3.2f;
constexpr float kYfov = 0.75f;

Scene furnace_scene(const fs::path& dir, const std::string& name, float roughness) {
    write_bumpy_normal_map(dir / "bumps.png", 256, 128);
    test::GltfBuilder b;
    b.json()["images"] = {{{"uri", "bumps.png"}}};
    b.json()["samplers"] = {{{"magFilter", 9729}, {"minFilter", 9987}}};
    b.json()["textures"] = {{{"source", 0}, {"sampler", 0}}};
    b.json()["materials"] = {{{"pbrMetallicRoughness", {{"baseColorFactor", {1, 1, 1, 1}}, {"metallicFactor", 1}, {"roughnessFactor", roughness}}},
                              {"normalTexture", {{"index", 0}}}}};
    b.add_node({{"mesh", add_uv_sphere(b, 0)}});
    b.json()["scenes"][0]["extras"]["environment_radiance"] = {1, 1, 1};
    b.json()["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", kYfov}, {"znear", 0.1}}}}};
    b.add_node({{"camera", 0}, {"translation", {0, 0, kCameraDistance}}});
    return load_gltf(b.write(dir, name));
}

// The geometric cosine at the point of the unit sphere that pixel (x, y)'s centre ray meets (the
// camera above, square image); 0 if it misses.
float pixel_cosine(int x, int y, int n) {
    const float t = std::tan(kYfov * 0.5f);
    const glm::vec3 d = glm::normalize(glm::vec3(((static_cast<float>(x) + 0.5f) / static_cast<float>(n) * 2.0f - 1.0f) * t,
                                                 (1.0f - (static_cast<float>(y) + 0.5f) / static_cast<float>(n) * 2.0f) * t, -1.0f));
    const glm::vec3 o(0.0f, 0.0f, kCameraDistance);
    const float perp2 = glm::dot(glm::cross(o, d), glm::cross(o, d));
    return perp2 < 1.0f ? std::sqrt(1.0f - perp2) : 0.0f;
}

class RtNormalMapTest : public test::GlContextTest {
protected:
    ShaderLibrary lib_{ShaderLibrary::default_root()};  // CANDELA_SHADER_DIR when set
};

struct Batches {
    ImageF mean, standard_error;  // per pixel, channel 0
};

// `count` independent renders (seeds 1..count) of `spp` samples; the per-pixel mean and its
// standard error from the spread of the batch means.
Batches trace_batches(const ShaderLibrary& lib, const Scene& scene, rt::Mode mode, int n, int count, int spp) {
    std::vector<ImageF> runs;
    for (int k = 0; k < count; ++k) {
        rt::Options o;
        o.mode = mode;
        o.spp = spp;
        o.seed = static_cast<std::uint32_t>(k + 1);
        GpuScene gpu(scene);
        rt::Result r = rt::RayTracer(lib, scene, gpu, o).render(scene.select_camera("", 1.0f), n, n);
        EXPECT_EQ(r.nonfinite_samples, 0u);
        EXPECT_EQ(count_nonfinite(r.image), 0u);
        runs.push_back(std::move(r.image));
    }
    Batches b{ImageF(n, n, 4), ImageF(n, n, 4)};
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            double s = 0.0, s2 = 0.0;
            for (const ImageF& im : runs) {
                s += im.at(x, y)[0];
                s2 += static_cast<double>(im.at(x, y)[0]) * im.at(x, y)[0];
            }
            const double m = s / count, var = std::max(0.0, (s2 - s * m) / (count - 1));
            for (int c = 0; c < 3; ++c) {
                b.mean.at(x, y)[c] = static_cast<float>(m);
                b.standard_error.at(x, y)[c] = static_cast<float>(std::sqrt(var / count));
            }
            b.mean.at(x, y)[3] = b.standard_error.at(x, y)[3] = 1.0f;
        }
    return b;
}

TEST_P(RtNormalMapTest, NormalMappedMetalInAWhiteFurnaceStaysWithinItsAlbedoAndMatchesTheRaster) {
    const int n = 72, batches = 16, spp = 8;
    for (const float roughness : {0.05f, 0.6f}) {
        const std::string name = roughness < 0.1f ? "smooth" : "rough";
        SCOPED_TRACE(name);
        const fs::path dir = test::test_dir("normal_furnace_" + name);
        const Scene scene = furnace_scene(dir, name, roughness);
        const float alpha = std::max(roughness * roughness, 1e-3f);  // brdf_alpha()
        const double e_min = ggx_white_albedo_min(alpha);

        const Batches path = trace_batches(lib_, scene, rt::Mode::path, n, batches, spp);
        StillOptions so;
        so.width = so.height = n;
        so.settings.path = RenderPath::forward;
        apply_effects(so.settings, "reflections");  // no SSAO: a furnace has nothing to occlude
        const StillResult raster = render_still(scene, lib_, so);
        EXPECT_EQ(count_nonfinite(raster.radiance), 0u);
        // Radiance 1 is white in these PNGs (no tone mapping): a dark ring shows as one.
        write_display_image(dir / "path.png", path.mean);
        write_display_image(dir / "raster.png", raster.radiance);
        std::printf("images: %s\n", dir.string().c_str());

        // (a) Every pixel within [E_min, 1]: the lower side with 4 standard errors (16 batches:
        // a t distribution with 15 degrees of freedom, so a pass rate, not every pixel) and a
        // quadrature allowance of 0.005; none below 0.5 at all; the upper side exact.
        int sphere_pixels = 0, below = 0, dark = 0, above = 0;
        float lowest = 2.0f;
        double trace_sum = 0.0, raster_sum = 0.0, interior = 0.0;
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) {
                const float m = path.mean.at(x, y)[0], se = path.standard_error.at(x, y)[0];
                const float mu_g = pixel_cosine(x, y, n);
                sphere_pixels += mu_g > 0.0f;
                lowest = std::min(lowest, m);
                below += m < e_min - 0.005 - 4.0 * se;
                dark += m < 0.5f;
                above += m > 1.0f + 1e-4f;
                if (mu_g >= 0.3f) {  // (b) away from the silhouette, where anti-aliasing differs
                    trace_sum += m;
                    raster_sum += raster.radiance.at(x, y)[0];
                    interior += 1.0;
                }
            }
        // The standard error of the interior mean, from the batch means of the interior.
        const double trace_mean = trace_sum / interior, raster_mean = raster_sum / interior;
        double se2_sum = 0.0;  // pixels are independent (each has its own sample streams)
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x)
                if (pixel_cosine(x, y, n) >= 0.3f) se2_sum += std::pow(path.standard_error.at(x, y)[0], 2.0);
        const double mean_se = std::sqrt(se2_sum) / interior;
        std::printf("%s (roughness %.2f): E_min %.4f; %d sphere pixels, lowest %.4f, %d below E_min - 4 se, %d below 0.5, "
                    "%d above 1; interior mean path %.4f +- %.4f, raster %.4f (difference %.4f)\n",
                    name.c_str(), roughness, e_min, sphere_pixels, lowest, below, dark, above, trace_mean, mean_se, raster_mean,
                    trace_mean - raster_mean);
        EXPECT_GT(sphere_pixels, n * n / 3);
        EXPECT_EQ(dark, 0);
        EXPECT_EQ(above, 0);
        EXPECT_LE(below, n * n / 1000);
        // (b) The raster's split-sum term is the same albedo from a 2D table: the means agree to
        // 0.02 plus 4 standard errors.
        EXPECT_NEAR(trace_mean, raster_mean, 0.02 + 4.0 * mean_se);
        // The furnace must not pass on a black or blank image: the sphere is there and not 0.
        EXPECT_GT(raster_mean, 0.5);
        EXPECT_GT(trace_mean, 0.5);
    }
}

TEST_P(RtNormalMapTest, WhittedMirrorWithANormalMapReflectsTheWhiteEnvironmentEverywhere) {
    // Roughness 0.05 is a mirror in whitted mode (rt.whitted_max_roughness): each camera ray
    // reflects once with Fresnel 1 and escapes to radiance 1, so every pixel is exactly 1.
    const int n = 72;
    const fs::path dir = test::test_dir("normal_furnace_whitted");
    const Scene scene = furnace_scene(dir, "mirror", 0.05f);
    rt::Options o;
    o.mode = rt::Mode::whitted;
    o.spp = 4;
    GpuScene gpu(scene);
    const rt::Result r = rt::RayTracer(lib_, scene, gpu, o).render(scene.select_camera("", 1.0f), n, n);
    EXPECT_EQ(r.nonfinite_samples, 0u);
    EXPECT_EQ(count_nonfinite(r.image), 0u);
    write_display_image(dir / "whitted.png", r.image);
    int off = 0, sphere = 0;
    float lowest = 2.0f;
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            const float v = r.image.at(x, y)[0];
            sphere += pixel_cosine(x, y, n) > 0.0f;
            lowest = std::min(lowest, v);
            off += std::fabs(v - 1.0f) > 1e-4f;
        }
    std::printf("whitted mirror: %d sphere pixels, %d pixels off 1 by more than 1e-4, lowest %.4f\n", sphere, off, lowest);
    EXPECT_GT(sphere, n * n / 3);
    EXPECT_EQ(off, 0);
}

INSTANTIATE_TEST_SUITE_P(Backends, RtNormalMapTest, ::testing::Values(Backend::egl, Backend::osmesa), test::backend_name);

}  // namespace
}  // namespace candela
