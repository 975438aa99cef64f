// The compute-shader ray tracer on materials: alpha-masked holes, normal maps (also mirrored),
// texture wrap and filter modes against the rasterizer, emissive spheres sampled by their cone and
// emissive textures through next-event estimation.
#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <random>

#include "gl_fixture.hpp"
#include "gltf_builder.hpp"
#include "platform/context.hpp"
#include "render/still.hpp"
#include "rt/ray_tracer.hpp"
#include "scene/gltf_loader.hpp"
#include "rt_test_scenes.hpp"

namespace candela {
namespace {
namespace fs = std::filesystem;
using nlohmann::json;
using test::add_sphere;
using test::kLookDown;
using test::lambert;
using test::ortho_camera;
using test::shader_lib;
}  // namespace
}  // namespace candela

namespace candela {
namespace {

class RtMaterialTest : public test::GlContextTest {};

TEST_P(RtMaterialTest, AlphaMaskedTexelsAreHolesForRays) {
    // transparency.gltf has a fence quad facing the camera (normal +Z) with an alpha-masked
    // texture, standing on the floor (normal +Y). Through its holes camera rays reach the floor:
    // in the fence's rows some pixels must show the floor's normal. Without the mask none would.
    const Scene scene = load_gltf(fs::path(CANDELA_SOURCE_DIR) / "samples/scenes/transparency.gltf");
    rt::Options o;
    o.mode = rt::Mode::primary;
    o.spp = 1;
    GpuScene gpu(scene);
    rt::RayTracer tracer(shader_lib(), scene, gpu, o);
    const rt::Result r = tracer.render(scene.select_camera("", 1.0f), 96, 96);
    int floor_through_fence = 0, fence = 0;
    for (int y = 70; y <= 78; ++y)
        for (int x = 0; x < 96; ++x) {
            const float* p = r.image.at(x, y);
            floor_through_fence += p[1] > 0.9f && p[2] < 0.7f;  // normal ~ +Y
            fence += p[2] > 0.9f && p[1] < 0.7f;                // normal ~ +Z
        }
    EXPECT_GT(floor_through_fence, 20);
    EXPECT_GT(fence, 20);
}

INSTANTIATE_TEST_SUITE_P(Backends, RtMaterialTest, ::testing::Values(Backend::egl), test::backend_name);

}  // namespace
}  // namespace candela

namespace candela {
namespace {

TEST_P(RtMaterialTest, NormalMapsAgreeBetweenRasterAndTracerAlsoWhenMirrored) {
    // A white Lambert quad facing +Z with a constant normal map tilted 45 degrees towards +v
    // (image up = world +Y), lit by a directional light coming from +Y+Z: the mapped normal faces
    // the light, so the radiance is E / pi instead of cos(45) * E / pi without the map. A node
    // mirrored in X must give the same (mirroring X leaves the Y tilt alone).
    const auto dir = test::test_dir("normal_map");
    std::vector<unsigned char> rgba(4 * 4 * 4);
    for (size_t i = 0; i < 16; ++i) {
        rgba[i * 4 + 0] = 128;
        rgba[i * 4 + 1] = static_cast<unsigned char>(std::lround((0.70710678 + 1.0) * 0.5 * 255.0));
        rgba[i * 4 + 2] = static_cast<unsigned char>(std::lround((0.70710678 + 1.0) * 0.5 * 255.0));
        rgba[i * 4 + 3] = 255;
    }
    write_display_rgba8(dir / "tilt.png", rgba, 4, 4);
    for (const bool mirrored : {false, true}) {
        SCOPED_TRACE(mirrored ? "mirrored" : "plain");
        test::GltfBuilder b;
        b.json()["images"] = {{{"uri", "tilt.png"}}};
        b.json()["samplers"] = {{{"magFilter", 9728}, {"minFilter", 9728}}};
        b.json()["textures"] = {{{"source", 0}, {"sampler", 0}}};
        json m = lambert(glm::vec3(1.0f));
        m["normalTexture"] = {{"index", 0}};
        b.json()["materials"] = {m};
        json quad = {{"mesh", b.add_quad_mesh(0)}};
        if (mirrored) quad["scale"] = {-1, 1, 1};
        b.add_node(quad);
        b.json()["extensions"]["KHR_lights_punctual"]["lights"] = {{{"type", "directional"}, {"intensity", 1.0}}};
        b.add_node({{"rotation", {-0.38268343, 0, 0, 0.92387953}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
        ortho_camera(b, {0, 0, 5}, {0, 0, 0, 1}, 2.0f);
        const Scene scene = load_gltf(b.write(dir, mirrored ? "mirrored" : "plain"));
        rt::Options o;
        o.mode = rt::Mode::direct;
        o.spp = 1;
        GpuScene gpu(scene);
        const rt::Result traced = rt::RayTracer(shader_lib(), scene, gpu, o).render(scene.select_camera("", 1.0f), 16, 16);
        StillOptions so;
        so.width = so.height = 16;
        const StillResult raster = render_still(scene, shader_lib(), so);
        const float expected = 1.0f / 3.14159265f;
        // 8-bit texels quantise the normal: the cosine is within ~0.5 % of 1.
        EXPECT_NEAR(traced.image.at(8, 8)[0], expected, expected * 0.01f);
        EXPECT_NEAR(raster.radiance.at(8, 8)[0], expected, expected * 0.01f);
    }
}

}  // namespace
}  // namespace candela

namespace candela {
namespace {

// An emissive quad (texture `texture_info` over `uri` with `sampler`) filling an orthographic
// view, seen n x n by the tracer (whitted, no jitter) and by the rasterizer; both checked for NaN.
struct TexturedQuad {
    ImageF traced, raster;
};
TexturedQuad render_textured_quad(const fs::path& dir, const std::string& name, const std::string& uri, const json& sampler,
                                  const json& texture_info, int n) {
    test::GltfBuilder b;
    b.json()["images"] = {{{"uri", uri}}};
    b.json()["samplers"] = {sampler};
    b.json()["textures"] = {{{"source", 0}, {"sampler", 0}}};
    json m = lambert(glm::vec3(0.0f));
    m["emissiveFactor"] = {1, 1, 1};
    m["emissiveTexture"] = texture_info;
    b.json()["materials"] = {m};
    b.add_node({{"mesh", b.add_quad_mesh(0)}});
    ortho_camera(b, {0, 0, 5}, {0, 0, 0, 1}, 1.0f);
    const Scene scene = load_gltf(b.write(dir, name));
    rt::Options o;
    o.mode = rt::Mode::whitted;
    o.jitter = 0;
    o.spp = 1;
    GpuScene gpu(scene);
    TexturedQuad q;
    q.traced = rt::RayTracer(shader_lib(), scene, gpu, o).render(scene.select_camera("", 1.0f), n, n).image;
    StillOptions so;
    so.width = so.height = n;
    so.settings.set_on("ssao", false);
    q.raster = render_still(scene, shader_lib(), so).radiance;
    EXPECT_EQ(count_nonfinite(q.traced), 0u);
    EXPECT_EQ(count_nonfinite(q.raster), 0u);
    return q;
}

TEST_P(RtMaterialTest, TextureWrapModesMatchTheRasterizer) {
    // An emissive quad whose texture (a black and a white texel) is stretched over uv -1..2 by
    // KHR_texture_transform: with CLAMP_TO_EDGE and MIRRORED_REPEAT the ray tracer (one
    // repeating texture array) must show what the rasterizer's samplers show.
    const auto dir = test::test_dir("wrap");
    const std::vector<unsigned char> rgba = {0, 0, 0, 255, 255, 255, 255, 255};
    write_display_rgba8(dir / "two.png", rgba, 2, 1);
    for (const int wrap : {33071, 33648}) {
        SCOPED_TRACE(wrap);
        const json sampler = {{"magFilter", 9728}, {"minFilter", 9728}, {"wrapS", wrap}, {"wrapT", wrap}};
        const json transform = {{"offset", {-1, 0}}, {"scale", {3, 1}}};
        const int n = 60;
        const TexturedQuad q = render_textured_quad(dir, wrap == 33071 ? "clamp" : "mirror", "two.png", sampler,
                                                    {{"index", 0}, {"extensions", {{"KHR_texture_transform", transform}}}}, n);
        int agree = 0;
        for (int x = 0; x < n; ++x) agree += (q.traced.at(x, n / 2)[0] > 0.5f) == (q.raster.at(x, n / 2)[0] > 0.5f);
        // Both sample NEAREST: at most one pixel whose centre sits on a texel border may differ.
        EXPECT_GE(agree, n - 1);
        // u = 0.75 -> uv 1.25: white when clamped or mirrored (black if it repeated).
        EXPECT_GT(q.traced.at(n * 3 / 4, n / 2)[0], 0.5f);
        // u = 0.1 -> uv -0.7: black when clamped, white when mirrored.
        EXPECT_EQ(q.traced.at(n / 10, n / 2)[0] > 0.5f, wrap == 33648);
    }
}

}  // namespace
}  // namespace candela

namespace candela {
namespace {

TEST_P(RtMaterialTest, TextureFilterModesMatchTheRasterizer) {
    // A 4x4 black/white checker magnified 15 times on an emissive quad. With magFilter NEAREST the
    // ray tracer, like the rasterizer, shows only black and white (no pixel in between, sampled
    // without jitter); with LINEAR both blend across every texel border, and agree with each other.
    const auto dir = test::test_dir("filter");
    std::vector<unsigned char> rgba(4 * 4 * 4, 255);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x)
            if ((x + y) % 2) rgba[static_cast<size_t>((y * 4 + x) * 4)] = rgba[static_cast<size_t>((y * 4 + x) * 4 + 1)] =
                                 rgba[static_cast<size_t>((y * 4 + x) * 4 + 2)] = 0;
    write_display_rgba8(dir / "checker.png", rgba, 4, 4);
    for (const int filter : {9728, 9729}) {
        SCOPED_TRACE(filter);
        const json sampler = {{"magFilter", filter}, {"minFilter", filter}, {"wrapS", 33071}, {"wrapT", 33071}};
        const int n = 60;
        const TexturedQuad q = render_textured_quad(dir, filter == 9728 ? "nearest" : "linear", "checker.png", sampler,
                                                    {{"index", 0}}, n);
        int between_rt = 0, between_raster = 0;
        double max_diff = 0.0;
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) {
                const float t = q.traced.at(x, y)[0], r = q.raster.at(x, y)[0];
                between_rt += t > 0.02f && t < 0.98f;
                between_raster += r > 0.02f && r < 0.98f;
                max_diff = std::max(max_diff, static_cast<double>(std::abs(t - r)));
            }
        std::printf("magFilter %d: pixels between black and white: ray tracer %d, raster %d; max difference %.3f\n", filter,
                    between_rt, between_raster, max_diff);
        if (filter == 9728) {
            EXPECT_EQ(between_rt, 0);
            EXPECT_EQ(between_raster, 0);
        } else {
            EXPECT_GT(between_rt, n * n / 4);
            EXPECT_GT(between_raster, n * n / 4);
        }
        EXPECT_LT(max_diff, filter == 9728 ? 1e-3 : 0.1);
    }
}

TEST_P(RtMaterialTest, EmissiveSpheresAreSampledByTheirCone) {
    // A Lambert floor (albedo 1) lit only by an emissive sphere of radius 0.25 and radiance 4,
    // centred 2 above the floor's origin. At a floor point at distance d from the centre,
    // Lo = albedo / pi * pi L r^2 cos(theta) / d^2 = L r^2 h / d^3 (exact for a sphere wholly above
    // the horizon). The camera sees the square x in [1, 2], z in [-0.5, 0.5]. At 16 spp the sphere
    // (0.05 sr) is found by next-event estimation in every sample; BRDF rays alone hit it about
    // once in 80 and would leave most pixels black.
    test::GltfBuilder b;
    json light = lambert(glm::vec3(0.0f));
    light["emissiveFactor"] = {4, 4, 4};
    b.json()["materials"] = {lambert(glm::vec3(1.0f)), light};
    b.add_node({{"mesh", b.add_quad_mesh(0)}, {"rotation", {-0.70710678, 0, 0, 0.70710678}}, {"scale", {6, 6, 6}}});
    const float r = 0.25f, h = 2.0f, L = 4.0f;
    b.add_node({{"mesh", add_sphere(b, r, 1)}, {"translation", {0, h, 0}}, {"extras", {{"sphere", {{"radius", r}}}}}});
    ortho_camera(b, {1.5f, 5.0f, 0.0f}, kLookDown, 0.5f);
    const Scene scene = load_gltf(b.write(test::test_dir("emissive_sphere"), "sphere"));
    const int n = 16;
    std::vector<double> expected, got;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const double x = 1.0 + (i + 0.5) / n, z = -0.5 + (j + 0.5) / n;
            const double d = std::sqrt(x * x + h * h + z * z);
            expected.push_back(L * r * r * h / (d * d * d));
        }
    rt::Options o;
    o.mode = rt::Mode::direct;
    o.spp = 16;
    GpuScene gpu(scene);
    const rt::Result res = rt::RayTracer(shader_lib(), scene, gpu, o).render(scene.select_camera("", 1.0f), n, n);
    EXPECT_EQ(res.nonfinite_samples, 0u);
    EXPECT_EQ(count_nonfinite(res.image), 0u);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) got.push_back(res.image.at(x, y)[0]);
    // The mean and the sorted values do not depend on how the image is oriented on the floor.
    double mean_e = 0.0, mean_g = 0.0;
    for (size_t k = 0; k < expected.size(); ++k) mean_e += expected[k] / expected.size(), mean_g += got[k] / got.size();
    std::sort(expected.begin(), expected.end());
    std::sort(got.begin(), got.end());
    double worst = 0.0;
    for (size_t k = 0; k < expected.size(); ++k) worst = std::max(worst, std::abs(got[k] - expected[k]) / expected[k]);
    std::printf("emissive sphere: mean %.5f (analytic %.5f), worst sorted pixel off by %.2f %%\n", mean_g, mean_e, 100.0 * worst);
    EXPECT_NEAR(mean_g, mean_e, 0.01 * mean_e);
    EXPECT_LT(worst, 0.05);
}

TEST_P(RtMaterialTest, EmissiveTexturesLightThroughNextEventEstimation) {
    // An area light whose emissive texture is black on one half and white on the other must light
    // the floor like an untextured light covering only the white half: next-event estimation
    // reads the texture at the point it samples, as BRDF rays hitting the light do.
    const auto dir = test::test_dir("emissive_texture");
    // 64 texels wide and NEAREST, so the black/white border is sharp in both renderers.
    std::vector<unsigned char> rgba(64 * 4, 255);
    for (int x = 0; x < 32; ++x) rgba[static_cast<size_t>(x * 4)] = rgba[static_cast<size_t>(x * 4 + 1)] = rgba[static_cast<size_t>(x * 4 + 2)] = 0;
    write_display_rgba8(dir / "half.png", rgba, 64, 1);
    auto render = [&](bool textured) {
        test::GltfBuilder b;
        json light = lambert(glm::vec3(0.0f));
        light["emissiveFactor"] = {4, 4, 4};
        if (textured) {
            b.json()["images"] = {{{"uri", "half.png"}}};
            b.json()["samplers"] = {{{"magFilter", 9728}, {"minFilter", 9728}, {"wrapS", 33071}, {"wrapT", 33071}}};
            b.json()["textures"] = {{{"source", 0}, {"sampler", 0}}};
            light["emissiveTexture"] = {{"index", 0}};
        }
        b.json()["materials"] = {lambert(glm::vec3(1.0f)), light};
        b.add_node({{"mesh", b.add_quad_mesh(0)}, {"rotation", {-0.70710678, 0, 0, 0.70710678}}, {"scale", {6, 6, 6}}});
        // The light faces down at height 1, beside the camera's view; untextured: only its
        // white half (local x in [0, 1]).
        json quad = {{"mesh", b.add_quad_mesh(1)}, {"rotation", {0.70710678, 0, 0, 0.70710678}}};
        if (textured) {
            quad["translation"] = {2.5, 1, 0};
        } else {
            quad["translation"] = {3.0, 1, 0};
            quad["scale"] = {0.5, 1, 1};
        }
        b.add_node(quad);
        ortho_camera(b, {0, 5, 0}, kLookDown, 1.0f);
        const Scene scene = load_gltf(b.write(dir, textured ? "textured" : "half"));
        rt::Options o;
        o.mode = rt::Mode::direct;
        o.spp = 256;
        GpuScene gpu(scene);
        const rt::Result r = rt::RayTracer(shader_lib(), scene, gpu, o).render(scene.select_camera("", 1.0f), 16, 16);
        EXPECT_EQ(r.nonfinite_samples, 0u);
        EXPECT_EQ(count_nonfinite(r.image), 0u);
        double sum = 0.0;
        for (int y = 0; y < 16; ++y)
            for (int x = 0; x < 16; ++x) sum += r.image.at(x, y)[0];
        return sum / 256.0;
    };
    const double textured = render(true), half = render(false);
    ASSERT_GT(half, 0.01);
    EXPECT_NEAR(textured, half, 0.03 * half);
}

}  // namespace
}  // namespace candela
