// The tracer judged against closed forms, statistically (a reference must be unbiased). Each case renders
// kBatches independent batches (the --spp-shard k/N sample sets of one render), estimates each
// pixel's standard error from them and compares with the closed form (engine/image/batch_stats):
// - at least kPassRate of the pixels pass |z| < kPixelZ, and
// - the z of the image mean is below kMeanZ in magnitude (per RGB channel).
// A fixed tolerance would hide a bias below it; these fail on any bias that the batches resolve.
// Each case also shows its power: the same batches against the closed form scaled by 1 -+ 0.1 %
// (a tracer 0.1 % dark or bright) fail the z of the mean, and the cause the case targets, put
// back (a depth cap, camera rays through pixel centres), fails the test.
#include <gtest/gtest.h>

#include <glm/gtc/constants.hpp>

#include <algorithm>
#include <array>
#include <cstdlib>
#include <cmath>
#include <functional>
#include <vector>

#include "closed_form_judge.hpp"
#include "gl_fixture.hpp"
#include "gltf_builder.hpp"
#include "image/batch_stats.hpp"
#include "rt/ray_tracer.hpp"
#include "scene/gltf_loader.hpp"

namespace candela {
namespace {
namespace fs = std::filesystem;
using nlohmann::json;

constexpr int kBatches = 16;
using test::kMeanZ;
using test::kPassRate;
using test::kPixelZ;
using test::worst_mean_z;
constexpr double kPi = glm::pi<double>();

// --- closed forms ---------------------------------------------------------------------------

// Irradiance at p (normal n) from a uniform Lambertian polygon of radiance 1 wholly above p's
// horizon and facing p: Lambert's formula, E = 1/2 sum_i beta_i (n . gamma_i), beta_i the angle the
// edge (v_i, v_i+1) subtends at p and gamma_i the unit normal of the plane through p and the edge
// (Arvo 1995, "Applications of irradiance tensors", eq. 9). 0 if the polygon faces away from p
// (one-sided emitter with normal `facing`).
double lambert_polygon_irradiance(const glm::dvec3& p, const glm::dvec3& n, const std::vector<glm::dvec3>& poly,
                                  const glm::dvec3& facing) {
    if (glm::dot(poly[0] - p, facing) >= 0.0) return 0.0;  // p is behind the emitting side
    double sum = 0.0;
    for (size_t i = 0; i < poly.size(); ++i) {
        const glm::dvec3 a = glm::normalize(poly[i] - p), b = glm::normalize(poly[(i + 1) % poly.size()] - p);
        const double beta = std::acos(std::clamp(glm::dot(a, b), -1.0, 1.0));
        sum += beta * glm::dot(n, glm::normalize(glm::cross(a, b)));
    }
    return 0.5 * std::fabs(sum);
}

// The cosine-weighted solid-angle fraction of the polygon seen from p: Lambert's formula / pi.
double form_factor(const glm::dvec3& p, const glm::dvec3& n, const std::vector<glm::dvec3>& poly) {
    double sum = 0.0;
    for (size_t i = 0; i < poly.size(); ++i) {
        const glm::dvec3 a = glm::normalize(poly[i] - p), b = glm::normalize(poly[(i + 1) % poly.size()] - p);
        sum += std::acos(std::clamp(glm::dot(a, b), -1.0, 1.0)) * glm::dot(n, glm::normalize(glm::cross(a, b)));
    }
    return std::fabs(sum) / (2.0 * kPi);
}

// The box-filtered pixel value of f over the pixel: a q x q midpoint rule (exact enough for the
// smooth or kinked closed forms below: the error is far below the batches' standard error).
ImageF pixel_average(int w, int h, int q, const std::function<glm::dvec3(double, double)>& f) {
    ImageF img(w, h, 4);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            glm::dvec3 sum(0.0);
            for (int j = 0; j < q; ++j)
                for (int i = 0; i < q; ++i) sum += f(x + (i + 0.5) / q, y + (j + 0.5) / q);
            sum /= static_cast<double>(q * q);
            float* px = img.at(x, y);
            px[0] = static_cast<float>(sum.x), px[1] = static_cast<float>(sum.y), px[2] = static_cast<float>(sum.z), px[3] = 1.0f;
        }
    return img;
}

ImageF scaled(ImageF img, double s) {
    for (size_t i = 0; i < img.pixels.size(); ++i)
        if (i % 4 != 3) img.pixels[i] = static_cast<float>(img.pixels[i] * s);
    return img;
}

// --- scenes -----------------------------------------------------------------------------------

json lambert(glm::vec3 albedo, glm::vec3 emission = glm::vec3(0.0f)) {
    json m = {{"pbrMetallicRoughness", {{"baseColorFactor", {albedo.r, albedo.g, albedo.b, 1}}, {"metallicFactor", 0}, {"roughnessFactor", 1}}},
              {"extensions", {{"KHR_materials_specular", {{"specularFactor", 0}}}}}};
    if (emission != glm::vec3(0.0f)) {
        const float peak = std::max(emission.r, std::max(emission.g, emission.b));
        m["emissiveFactor"] = {emission.r / peak, emission.g / peak, emission.b / peak};
        if (peak > 1.0f) m["extensions"]["KHR_materials_emissive_strength"] = {{"emissiveStrength", peak}};
    }
    return m;
}

const json kLookDown = {-0.70710678, 0.0, 0.0, 0.70710678};  // -Z turned to -Y

// A white Lambert floor y = 0 over [-2, 2]^2 (material 0), seen straight from above by an
// orthographic camera: pixel (px, py) of an n x n image is floor point (-2 + 4 px / n, -2 + 4 py / n).
void floor_scene(test::GltfBuilder& b) {
    b.json()["materials"].push_back(lambert(glm::vec3(1.0f)));
    b.add_node({{"mesh", b.add_quad_mesh(0)}, {"rotation", kLookDown}, {"scale", {2, 2, 2}}});  // faces +Y
    b.json()["cameras"].push_back({{"type", "orthographic"}, {"orthographic", {{"xmag", 2}, {"ymag", 2}, {"znear", 0.01}, {"zfar", 100}}}});
    b.add_node({{"camera", 0}, {"translation", {0, 5, 0}}, {"rotation", kLookDown}});
}
glm::dvec3 floor_point(double px, double py, int n) { return {-2.0 + 4.0 * px / n, 0.0, -2.0 + 4.0 * py / n}; }

class RtStatisticsTest : public test::GlContextTest {
protected:
    // kBatches independent batches of `spp_per_batch` samples each (one tracer, --spp-shard k/N).
    // CANDELA_STAT_SAMPLES=K multiplies every sample count by K (a slower, more sensitive run).
    std::vector<ImageF> batches(const Scene& scene, rt::Options o, int w, int h, int spp_per_batch) {
        if (const char* k = std::getenv("CANDELA_STAT_SAMPLES")) spp_per_batch *= std::clamp(std::atoi(k), 1, 1024);
        o.spp = spp_per_batch * kBatches;
        GpuScene gpu(scene);
        rt::RayTracer tracer(shaders_, scene, gpu, o);
        const Camera camera = scene.select_camera("", static_cast<float>(w) / static_cast<float>(h));
        std::vector<ImageF> out;
        for (int k = 0; k < kBatches; ++k) {
            tracer.set_shard(k, kBatches);
            rt::Result r = tracer.render(camera, w, h);
            EXPECT_EQ(r.samples, spp_per_batch);
            EXPECT_EQ(r.nonfinite_samples, 0u);
            EXPECT_EQ(count_nonfinite(r.image), 0u);
            out.push_back(std::move(r.image));
        }
        return out;
    }
    static BatchCompareResult judge(const std::vector<ImageF>& b, const ImageF& reference) { return test::judge_against_closed_form(b, reference); }
    static std::string describe(const BatchCompareResult& r) {
        char s[256];
        std::snprintf(s, sizeof(s), "pixels passing %.3f %% (|z| < %.0f), z of the mean %+.2f (rgb %+.2f %+.2f %+.2f), relative %+.5f %%",
                      100.0 * r.passing_fraction, r.z_threshold, r.z_of_mean, r.z_of_mean_rgb.x, r.z_of_mean_rgb.y, r.z_of_mean_rgb.z,
                      100.0 * r.relative_difference);
        return s;
    }
    static bool fails(const BatchCompareResult& r) { return r.passing_fraction < kPassRate || worst_mean_z(r) >= kMeanZ; }
    // The failing pixels with the largest |z| (for the failure message).
    static std::string worst_pixels(const BatchCompareResult& r, int width, const ImageF& reference, const std::vector<ImageF>& b) {
        std::vector<size_t> order(r.z.size());
        for (size_t i = 0; i < order.size(); ++i) order[i] = i;
        std::sort(order.begin(), order.end(), [&](size_t i, size_t j) { return std::fabs(r.z[i]) > std::fabs(r.z[j]); });
        std::string out;
        for (size_t k = 0; k < std::min<size_t>(8, order.size()) && std::fabs(r.z[order[k]]) >= kPixelZ; ++k) {
            const int x = static_cast<int>(order[k] % static_cast<size_t>(width)), y = static_cast<int>(order[k] / static_cast<size_t>(width));
            double mean = 0.0;
            for (const ImageF& i : b) mean += i.at(x, y)[0] / static_cast<double>(b.size());
            char line[160];
            std::snprintf(line, sizeof(line), "\n  (%d, %d) z %+.1f: red %.6g, closed form %.6g", x, y, r.z[order[k]], mean, reference.at(x, y)[0]);
            out += line;
        }
        return out;
    }
    // The case passes against its closed form, and fails against the closed form off by 0.1 %
    // either way: the batches resolve a 0.1 % bias.
    void expect_unbiased(const std::vector<ImageF>& b, const ImageF& reference, const std::string& what) {
        const BatchCompareResult r = judge(b, reference);
        std::printf("%s: %s\n", what.c_str(), describe(r).c_str());
        EXPECT_FALSE(fails(r)) << what << ": " << describe(r) << worst_pixels(r, reference.width, reference, b);
        for (double bias : {-0.001, 0.001}) {
            const BatchCompareResult off = judge(b, scaled(reference, 1.0 + bias));
            std::printf("%s against the closed form %+.1f %%: %s\n", what.c_str(), 100.0 * bias, describe(off).c_str());
            EXPECT_TRUE(fails(off)) << what << ": a " << 100.0 * bias << " % bias would go unseen: " << describe(off);
        }
    }
    // The cause put back fails the test (pass rate or z of the mean).
    void expect_caught(const std::vector<ImageF>& b, const ImageF& reference, const std::string& what) {
        const BatchCompareResult r = judge(b, reference);
        std::printf("%s: %s\n", what.c_str(), describe(r).c_str());
        EXPECT_TRUE(fails(r)) << what << " went unseen: " << describe(r);
    }
    // `direct` with the default jitter passes; through pixel centres (the old default) it fails.
    void direct_with_and_without_jitter(const Scene& scene, const ImageF& reference, const std::string& what, int spp) {
        rt::Options o;
        o.mode = rt::Mode::direct;
        expect_unbiased(batches(scene, o, reference.width, reference.height, spp), reference, what + ", direct");
        o.jitter = 0;
        expect_caught(batches(scene, o, reference.width, reference.height, 4), reference, what + ", direct, jitter off");
    }
    ShaderLibrary shaders_{fs::path(CANDELA_SOURCE_DIR) / "shaders"};
};

// A closed box lit only by its own uniform emission Le, albedo a per channel: every pixel sees
// radiance Le / (1 - a). With a = 0.9 a path tracer capped at N bounces is -a^(N+1) dark: -39 % at
// the old default of 8 and still -0.1 % at 64.
TEST_P(RtStatisticsTest, ClosedEmissiveBoxIsLeOverOneMinusAlbedo) {
    const glm::vec3 albedo(0.9f, 0.6f, 0.3f);
    const glm::vec3 Le(1.0f);
    test::GltfBuilder b;
    b.json()["materials"] = {lambert(albedo, Le)};
    const int quad = b.add_quad_mesh(0);
    const double h = 0.70710678;
    const std::vector<json> faces = {{0, 0, 0, 1}, {0, 1, 0, 0}, {0, h, 0, h}, {0, -h, 0, h}, {h, 0, 0, h}, {-h, 0, 0, h}};
    const std::vector<glm::vec3> offsets = {{0, 0, -1}, {0, 0, 1}, {-1, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}};
    for (size_t i = 0; i < faces.size(); ++i)  // inward-facing, overlapping at the seams: no gaps
        b.add_node({{"mesh", quad}, {"rotation", faces[i]}, {"translation", {offsets[i].x, offsets[i].y, offsets[i].z}}, {"scale", {1.001, 1.001, 1}}});
    b.json()["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 1.2}, {"znear", 0.01}}}}};
    b.add_node({{"camera", 0}, {"translation", {0.1, -0.2, 0.5}}});
    const Scene scene = load_gltf(b.write(test::test_dir("closed_box"), "closed_box"));
    const int n = 32;
    const glm::dvec3 exact = glm::dvec3(Le) / (1.0 - glm::dvec3(albedo));
    const ImageF reference = pixel_average(n, n, 1, [&](double, double) { return exact; });

    rt::Options o;
    o.mode = rt::Mode::path;  // default depth policy
    expect_unbiased(batches(scene, o, n, n, 32), reference, "closed box, path (default depth)");
    o.max_depth = 8;  // the old default
    expect_caught(batches(scene, o, n, n, 2), reference, "closed box, path --max-depth 8");
}

// Irradiance on a plane from a one-sided Lambertian quad light, by Lambert's formula. The light
// stands upright at x = -0.5 facing +X, 0.4 above the floor, so the floor points just in front of
// it are almost in its plane (cos at the light near 0) and those behind it get nothing.
TEST_P(RtStatisticsTest, QuadLightIrradianceIsLambertsFormula) {
    test::GltfBuilder b;
    floor_scene(b);
    const double Le = 4.0;
    b.json()["materials"].push_back(lambert(glm::vec3(0.0f), glm::vec3(static_cast<float>(Le))));
    // The unit quad (XY, facing +Z) turned 90 degrees about Y (facing +X), 1.2 wide in z, 1 tall.
    b.add_node({{"mesh", b.add_quad_mesh(1)}, {"translation", {-0.5, 1.3, 0.0}}, {"rotation", {0, 0.70710678, 0, 0.70710678}}, {"scale", {0.3, 0.3, 1}}});
    const Scene scene = load_gltf(b.write(test::test_dir("quad_light"), "quad_light"));
    const std::vector<glm::dvec3> light = {{-0.5, 1.0, -0.3}, {-0.5, 1.0, 0.3}, {-0.5, 1.6, 0.3}, {-0.5, 1.6, -0.3}};
    const int n = 64;
    const ImageF reference = pixel_average(n, n, 16, [&](double px, double py) {
        const double E = Le * lambert_polygon_irradiance(floor_point(px, py, n), {0, 1, 0}, light, {1, 0, 0});
        return glm::dvec3(E / kPi);  // white Lambert floor: L = E / pi
    });
    rt::Options o;
    o.mode = rt::Mode::direct;
    expect_unbiased(batches(scene, o, n, n, 48), reference, "quad light, direct");
}

// A point light over a Lambert plane: L = I cos / (pi d^2). No noise but the pixel footprint.
TEST_P(RtStatisticsTest, PointLightIsInverseSquareAndCosine) {
    test::GltfBuilder b;
    floor_scene(b);
    const glm::dvec3 pos(0.3, 1.2, -0.2);
    const double I = 10.0;
    b.json()["extensions"]["KHR_lights_punctual"]["lights"] = {{{"type", "point"}, {"intensity", I}}};
    b.add_node({{"translation", {pos.x, pos.y, pos.z}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
    const Scene scene = load_gltf(b.write(test::test_dir("point_light"), "point_light"));
    const int n = 64;
    const ImageF reference = pixel_average(n, n, 8, [&](double px, double py) {
        const glm::dvec3 d = pos - floor_point(px, py, n);
        const double d2 = glm::dot(d, d);
        return glm::dvec3(I * (d.y / std::sqrt(d2)) / d2 / kPi);
    });
    direct_with_and_without_jitter(scene, reference, "point light", 4);
}

// A spot light's cone edge: KHR_lights_punctual's falloff s^2, s = clamp((cos - cos_outer) /
// (cos_inner - cos_outer), 0, 1), on a Lambert plane; the image holds the whole cone and its edge.
TEST_P(RtStatisticsTest, SpotLightConeEdgeFollowsTheGltfFalloff) {
    test::GltfBuilder b;
    floor_scene(b);
    const glm::dvec3 pos(-0.2, 1.5, 0.1);
    const double I = 10.0, inner = 0.3, outer = 0.5;
    b.json()["extensions"]["KHR_lights_punctual"]["lights"] = {
        {{"type", "spot"}, {"intensity", I}, {"spot", {{"innerConeAngle", inner}, {"outerConeAngle", outer}}}}};
    b.add_node({{"translation", {pos.x, pos.y, pos.z}}, {"rotation", kLookDown}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
    const Scene scene = load_gltf(b.write(test::test_dir("spot_light"), "spot_light"));
    const int n = 64;
    const ImageF reference = pixel_average(n, n, 32, [&](double px, double py) {
        const glm::dvec3 d = pos - floor_point(px, py, n);
        const double d2 = glm::dot(d, d), dist = std::sqrt(d2);
        const double cos_axis = d.y / dist;  // the spot points down: angle between -Y and the ray to p
        const double s = std::clamp((cos_axis - std::cos(outer)) / (std::cos(inner) - std::cos(outer)), 0.0, 1.0);
        return glm::dvec3(I * s * s * (d.y / dist) / d2 / kPi);
    });
    direct_with_and_without_jitter(scene, reference, "spot light", 32);
}

// Pixel coverage of polygon edges at known sub-pixel positions under the box filter: emissive
// rectangles (radiance 1) over black, facing a perspective camera, with edges through the image
// centre and on its border rows and columns. A pixel's value is the exact area it has inside.
TEST_P(RtStatisticsTest, EdgeCoverageIsTheExactPixelArea) {
    const int n = 64;
    // Rectangles in pixel units [x0, x1] x [y0, y1] (y down), clipped to the image.
    const std::vector<std::array<double, 4>> rects = {
        {28.3, 35.6, 29.45, 34.8},   // around the centre
        {44.2, 63.56, 50.7, 63.3},   // right column 56 % and bottom row 30 % covered (the edges)
        {0.44, 12.5, 0.7, 10.25},    // left column and top row partly covered
        {-3.0, 9.8, 40.6, 70.0},     // across the left and bottom borders
    };
    // Camera at z = 4 looking down -Z with tan(yfov / 2) = 0.5: the plane z = 0 spans [-2, 2]^2.
    auto world_x = [&](double px) { return (px / n * 2.0 - 1.0) * 2.0; };
    auto world_y = [&](double py) { return (1.0 - py / n * 2.0) * 2.0; };
    test::GltfBuilder b;
    b.json()["materials"] = {lambert(glm::vec3(0.0f), glm::vec3(1.0f))};
    const int quad = b.add_quad_mesh(0);
    for (const auto& r : rects) {
        const double cx = 0.5 * (world_x(r[0]) + world_x(r[1])), cy = 0.5 * (world_y(r[2]) + world_y(r[3]));
        const double hx = 0.5 * (world_x(r[1]) - world_x(r[0])), hy = 0.5 * (world_y(r[2]) - world_y(r[3]));
        b.add_node({{"mesh", quad}, {"translation", {cx, cy, 0}}, {"scale", {hx, hy, 1}}});
    }
    b.json()["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 2.0 * std::atan(0.5)}, {"aspectRatio", 1.0}, {"znear", 0.1}}}}};
    b.add_node({{"camera", 0}, {"translation", {0, 0, 4}}});
    const Scene scene = load_gltf(b.write(test::test_dir("edge_coverage"), "edge_coverage"));
    ImageF reference(n, n, 4);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            double c = 0.0;
            for (const auto& r : rects)
                c += std::max(0.0, std::min(x + 1.0, r[1]) - std::max(x + 0.0, r[0])) * std::max(0.0, std::min(y + 1.0, r[3]) - std::max(y + 0.0, r[2]));
            float* px = reference.at(x, y);
            px[0] = px[1] = px[2] = static_cast<float>(c), px[3] = 1.0f;
        }
    EXPECT_NEAR(reference.at(63, 55)[0], 0.56, 1e-6);
    EXPECT_NEAR(reference.at(50, 63)[0], 0.30, 1e-6);
    rt::Options o;
    o.mode = rt::Mode::direct;  // default jitter
    expect_unbiased(batches(scene, o, n, n, 16), reference, "edge coverage, direct");
    o.jitter = 0;
    expect_caught(batches(scene, o, n, n, 1), reference, "edge coverage, direct, jitter off");
}

// White furnace: a Lambert sphere of albedo 1 under a uniform sky of radiance 1 is invisible (1
// everywhere); every sample is exactly 1, so any loss or gain of energy fails every pixel.
TEST_P(RtStatisticsTest, WhiteFurnaceIsOneEverywhere) {
    test::GltfBuilder b;
    b.json()["materials"] = {lambert(glm::vec3(1.0f))};
    b.add_node({{"mesh", b.add_quad_mesh(0)}, {"scale", {0.8, 0.8, 1}}});  // both sides seen: double-sided below
    b.json()["materials"][0]["doubleSided"] = true;
    b.json()["scenes"][0]["extras"]["environment_radiance"] = {1, 1, 1};
    b.json()["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0.8}, {"znear", 0.1}}}}};
    b.add_node({{"camera", 0}, {"translation", {0, 0, 3}}});
    const Scene scene = load_gltf(b.write(test::test_dir("furnace_stat"), "furnace_stat"));
    const int n = 32;
    const ImageF reference = pixel_average(n, n, 1, [](double, double) { return glm::dvec3(1.0); });
    rt::Options o;
    o.mode = rt::Mode::path;
    expect_unbiased(batches(scene, o, n, n, 4), reference, "white furnace, path");
}

// Ambient occlusion (radius far beyond the scene) of a floor next to an upright quad: the
// unoccluded cosine-weighted fraction is 1 - F, F the quad's form factor (Lambert's formula / pi),
// on both sides of the quad.
TEST_P(RtStatisticsTest, AmbientOcclusionIsOneMinusTheFormFactor) {
    test::GltfBuilder b;
    floor_scene(b);
    b.json()["materials"].push_back(lambert(glm::vec3(0.5f)));
    // Upright at x = 0.25 (a pixel boundary), standing on the floor across it: y in [0, 2], z in
    // [-2, 2]. It hides at least 10 % of every floor point's sky, so every pixel has AO samples
    // of both kinds (a pixel whose samples all agree would have a standard error of 0).
    b.add_node({{"mesh", b.add_quad_mesh(1)}, {"translation", {0.25, 1.0, 0.0}}, {"rotation", {0, 0.70710678, 0, 0.70710678}}, {"scale", {2.0, 1.0, 1}}});
    const Scene scene = load_gltf(b.write(test::test_dir("ao_wall"), "ao_wall"));
    const std::vector<glm::dvec3> wall = {{0.25, 0.0, -2.0}, {0.25, 0.0, 2.0}, {0.25, 2.0, 2.0}, {0.25, 2.0, -2.0}};
    const int n = 64;
    const ImageF reference = pixel_average(n, n, 8, [&](double px, double py) {
        return glm::dvec3(1.0 - form_factor(floor_point(px, py, n), {0, 1, 0}, wall));
    });
    rt::Options o;
    o.mode = rt::Mode::ao;
    o.ao_radius = 1000.0f;
    expect_unbiased(batches(scene, o, n, n, 128), reference, "ambient occlusion, radius 1000");
}

INSTANTIATE_TEST_SUITE_P(Backends, RtStatisticsTest, ::testing::Values(Backend::egl), test::backend_name);

}  // namespace
}  // namespace candela
