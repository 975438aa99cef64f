// Anti-aliasing: the raster edge profile converges to the tracer's box-filtered pixels
// as the sample count grows, on both backends and both render paths.
//
// The scene is a slanted square (rotated 5 degrees about the view axis) of emission 1 on black:
// no lights, so a pixel's exact value is the share of its area the square covers (the tracer's
// jittered camera rays estimate exactly that) and every difference is the edge's. The tracer's
// reference is itself checked against that closed form (z of the mean over independent batches).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <set>

#include <glm/gtc/matrix_transform.hpp>

#include "effects/aa/aa.hpp"
#include "box_reference.hpp"
#include "gl_fixture.hpp"
#include "gltf_builder.hpp"
#include "image/image.hpp"
#include "render/settings.hpp"
#include "render/still.hpp"
#include "rt/ray_tracer.hpp"
#include "scene/generate.hpp"
#include "scene/mesh_utils.hpp"

namespace candela {
namespace {

constexpr int kSize = 64;
constexpr float kDistance = 3.0f, kYfov = 0.7f, kAngle = 0.0872665f;  // 5 degrees
constexpr float kHalf = 0.55f;  // half side of the square, world units

// The square's corners in world space (plane z = 0), counter-clockwise seen from +z.
std::array<glm::vec3, 4> square_corners(float half, float angle) {
    std::array<glm::vec3, 4> c;
    const glm::vec2 q[4] = {{-half, -half}, {half, -half}, {half, half}, {-half, half}};
    for (int i = 0; i < 4; ++i) {
        const float x = q[i].x * std::cos(angle) - q[i].y * std::sin(angle);
        const float y = q[i].x * std::sin(angle) + q[i].y * std::cos(angle);
        c[static_cast<size_t>(i)] = glm::vec3(x + 0.07f, y - 0.03f, 0.0f);  // off-centre: no symmetry
    }
    return c;
}

Scene slanted_square_scene(AlphaMode alpha_mode = AlphaMode::opaque) {
    Scene scene;
    scene.source = "test:slanted_square";
    Material m;
    m.name = "emitter";
    m.base_color = glm::vec4(0.0f, 0.0f, 0.0f, 1.0f);
    m.emissive = glm::vec3(1.0f);
    m.metallic = 0.0f;
    m.roughness = 1.0f;
    m.alpha_mode = alpha_mode;
    scene.materials.push_back(m);
    Primitive p;
    p.material = 0;
    for (const glm::vec3& c : square_corners(kHalf, kAngle)) {
        Vertex v;
        v.position = c;
        v.normal = glm::vec3(0, 0, 1);
        p.vertices.push_back(v);
    }
    p.indices = {0, 1, 2, 0, 2, 3};
    compute_bounds(p);
    scene.meshes.push_back({"square", {std::move(p)}});
    Node n;
    n.name = "square";
    n.mesh = 0;
    scene.nodes.push_back(n);
    scene.roots.push_back(0);
    Camera cam;
    cam.name = "front";
    cam.yfov = kYfov;
    cam.znear = 0.1f;
    cam.world = glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 0.0f, kDistance));
    scene.cameras.push_back(cam);
    scene.update_world_transforms();
    return scene;
}

// The closed form: each pixel's covered share of its area (32 x 32 point grid per pixel; the
// grid's own error is below 1/32 of the pixel's edge length, about 0.002 on average).
std::vector<double> exact_coverage() {
    const auto corners = square_corners(kHalf, kAngle);
    const glm::mat4 proj = glm::perspective(kYfov, 1.0f, 0.1f, 100.0f);
    const glm::mat4 view = glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 0.0f, -kDistance));
    std::array<glm::vec2, 4> px;  // pixel coordinates, y down (image rows)
    for (size_t i = 0; i < 4; ++i) {
        const glm::vec4 c = proj * view * glm::vec4(corners[i], 1.0f);
        const glm::vec2 ndc = glm::vec2(c) / c.w;
        px[i] = glm::vec2((ndc.x * 0.5f + 0.5f) * kSize, (0.5f - ndc.y * 0.5f) * kSize);
    }
    auto inside = [&](glm::vec2 p) {
        int sign = 0;
        for (size_t i = 0; i < 4; ++i) {
            const glm::vec2 a = px[i], b = px[(i + 1) % 4];
            const float cr = (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x);
            const int s = cr > 0 ? 1 : -1;
            if (sign == 0) sign = s;
            else if (s != sign) return false;
        }
        return true;
    };
    std::vector<double> cov(static_cast<size_t>(kSize * kSize));
    const int g = 32;
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) {
            int hits = 0;
            for (int j = 0; j < g; ++j)
                for (int i = 0; i < g; ++i)
                    hits += inside({static_cast<float>(x) + (static_cast<float>(i) + 0.5f) / g, static_cast<float>(y) + (static_cast<float>(j) + 0.5f) / g});
            cov[static_cast<size_t>(y * kSize + x)] = static_cast<double>(hits) / (g * g);
        }
    return cov;
}

using Reference = test::BoxReference;

// `batches` independent traces of `spp` box-filtered samples each (box_reference.hpp).
Reference trace_reference(const ShaderLibrary& lib, const Scene& scene, int batches, int spp) {
    return test::trace_box_reference(lib, scene, kSize, kSize, batches, spp, 101u);
}

// `knob`: one more setting (KNOB=VALUE), if given.
ImageF raster(const ShaderLibrary& lib, const Scene& scene, RenderPath path, int samples, bool a2c = true, const std::string& knob = "") {
    StillOptions so;
    so.width = so.height = kSize;
    so.settings.path = path;
    apply_effects(so.settings, "none");
    if (samples > 1) {
        apply_knob(so.settings, "aa.mode=msaa");
        apply_knob(so.settings, "aa.samples=" + std::to_string(samples));
    }
    apply_knob(so.settings, std::string("aa.alpha_to_coverage=") + (a2c ? "1" : "0"));
    if (!knob.empty()) apply_knob(so.settings, knob);
    StillResult r = render_still(scene, lib, so);
    EXPECT_EQ(count_nonfinite(r.radiance), 0u);
    return std::move(r.radiance);
}

// Root of the mean squared difference over the edge pixels, less the reference's own variance
// (its squared standard error), so the tracer's noise does not count as raster error.
double edge_error(const ImageF& img, const Reference& ref, const std::vector<double>& cov) {
    double sum = 0;
    int n = 0;
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) {
            const size_t i = static_cast<size_t>(y * kSize + x);
            if (cov[i] <= 0.01 || cov[i] >= 0.99) continue;
            const double d = img.at(x, y)[0] - ref.mean[i];
            sum += d * d - ref.se[i] * ref.se[i];
            ++n;
        }
    return std::sqrt(std::max(0.0, sum / std::max(n, 1)));
}

struct AaCase {
    Backend backend;
    RenderPath path;
};
Backend case_backend(const AaCase& c) { return c.backend; }

class AaTest : public test::GlContextTestOf<AaCase, case_backend> {
protected:
    ShaderLibrary lib_{ShaderLibrary::default_root()};
};

TEST(AaPlanTest, SampleCountsTheDeviceLacksAreSubFramesWithARookPattern) {
    const std::vector<glm::vec2> d3d4 = {{-0.125f, -0.375f}, {0.375f, -0.125f}, {-0.375f, 0.125f}, {0.125f, 0.375f}};
    // A device with 4x only (llvmpipe): 2 = 2 single-sample sub-frames, 8 = 2 sub-frames of 4x.
    const AaPlan two = aa_plan_for(2, {1, 4}, d3d4);
    EXPECT_EQ(two.device_samples, 1);
    EXPECT_EQ(two.subframes, 2);
    const AaPlan eight = aa_plan_for(8, {1, 4}, d3d4);
    EXPECT_EQ(eight.device_samples, 4);
    ASSERT_EQ(eight.subframes, 2);
    // The union of the 8 positions is a rook pattern: 8 distinct columns and rows (1/64 grid),
    // every sample inside the pixel and the whole centred on it (an unbiased box filter).
    std::set<int> xs, ys;
    glm::vec2 mean(0.0f);
    for (glm::vec2 o : eight.offsets)
        for (glm::vec2 q : d3d4) {
            const glm::vec2 p = q + o;
            mean += p;
            EXPECT_LT(std::max(std::abs(p.x), std::abs(p.y)), 0.5f);
            xs.insert(static_cast<int>(std::lround(p.x * 64.0f)));
            ys.insert(static_cast<int>(std::lround(p.y * 64.0f)));
        }
    EXPECT_EQ(xs.size(), 8u);
    EXPECT_EQ(ys.size(), 8u);
    EXPECT_NEAR(mean.x / 8.0f, 0.0f, 1e-6f);
    EXPECT_NEAR(mean.y / 8.0f, 0.0f, 1e-6f);
    // A device with 2, 4 and 8: multisampling alone.
    const AaPlan hw8 = aa_plan_for(8, {1, 2, 4, 8}, {});
    EXPECT_EQ(hw8.device_samples, 8);
    EXPECT_EQ(hw8.subframes, 1);
}

TEST_P(AaTest, EdgeErrorAgainstTheTracerFallsWithEverySampleCount) {
    const AaCase c = GetParam();
    const Scene scene = slanted_square_scene();
    const std::vector<double> cov = exact_coverage();
    const int batches = 8;
    const Reference ref = trace_reference(lib_, scene, batches, 64);
    // The tracer's box filter is the closed form: z of the mean difference over the edge pixels.
    double dsum = 0, var = 0;
    int edge = 0;
    for (size_t i = 0; i < cov.size(); ++i)
        if (cov[i] > 0.01 && cov[i] < 0.99) {
            dsum += ref.mean[i] - cov[i];
            var += ref.se[i] * ref.se[i];
            ++edge;
        }
    ASSERT_GT(edge, 100);
    const double z = dsum / std::sqrt(var);
    std::printf("tracer vs closed form over %d edge pixels: mean difference %+.5f, z = %+.2f\n", edge, dsum / edge, z);
    EXPECT_LT(std::abs(z), 4.0) << "the tracer's box filter is biased against the exact coverage";

    double previous = 1e9;
    for (int samples : {1, 2, 4, 8}) {
        const ImageF img = raster(lib_, scene, c.path, samples);
        const double err = edge_error(img, ref, cov);
        // Interior pixels are exact either way (emission 1 / black).
        double interior = 0;
        for (int y = 0; y < kSize; ++y)
            for (int x = 0; x < kSize; ++x) {
                const double cv = cov[static_cast<size_t>(y * kSize + x)];
                if (cv == 0.0 || cv == 1.0) interior = std::max(interior, std::abs(img.at(x, y)[0] - cv));
            }
        std::printf("%s %s: %d sample(s): edge RMSE %.4f, interior max error %.2g\n", to_string(c.backend),
                    c.path == RenderPath::forward ? "forward" : "deferred", samples, err, interior);
        EXPECT_LT(interior, 1e-3) << samples << " samples";
        EXPECT_LT(err, previous) << samples << " samples: the edge error must fall with the sample count";
        previous = err;
        if (samples == 1) EXPECT_GT(err, 0.2) << "one sample per pixel: partly covered pixels are 0 or 1";
        if (samples == 8) EXPECT_LT(err, 0.08);
    }
}

// MASK materials: with alpha to coverage the alpha-tested contour is anti-aliased like a triangle
// edge; without it multisampling leaves it as aliased as one sample (forward: the fragment's
// alpha to the sample mask; deferred: gl_SampleMask in the G-buffer pass). The contour: the square is
// cut by a texture whose alpha falls linearly across it (cutoff 0.5: a slanted line).
TEST_P(AaTest, AlphaToCoverageAntiAliasesMaskContours) {
    const AaCase c = GetParam();
    Scene scene = slanted_square_scene(AlphaMode::mask);
    Image ramp;
    ramp.name = ramp.uri = "ramp";
    ramp.width = 16;
    ramp.height = 16;
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 16; ++x) {
            // alpha = 0.5 on the line x + 0.25 y = 9: a second slanted contour inside the square.
            const float a = std::clamp(0.5f + (9.0f - (static_cast<float>(x) + 0.5f) - 0.25f * (static_cast<float>(y) + 0.5f)) / 12.0f, 0.0f, 1.0f);
            for (int k = 0; k < 3; ++k) ramp.rgba8.push_back(255);
            ramp.rgba8.push_back(static_cast<std::uint8_t>(std::lround(a * 255.0f)));
        }
    ramp.valid = true;
    scene.images.push_back(ramp);
    Material& m = scene.materials[0];
    m.base_color_texture.image = 0;
    m.base_color_texture.sampler.min_filter = 9729;  // GL_LINEAR (magnified anyway)
    m.base_color_texture.sampler.wrap_s = m.base_color_texture.sampler.wrap_t = 33071;  // CLAMP_TO_EDGE
    Primitive& p = scene.meshes[0].primitives[0];
    const glm::vec2 uv[4] = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
    for (int i = 0; i < 4; ++i) p.vertices[static_cast<size_t>(i)].uv0 = uv[i];

    const int batches = 8;
    const Reference ref = trace_reference(lib_, scene, batches, 32);
    // Edge pixels: from the reference itself (partly covered by the square or the contour).
    std::vector<double> cov(ref.mean.size());
    for (size_t i = 0; i < cov.size(); ++i) cov[i] = ref.mean[i];
    const double err1 = edge_error(raster(lib_, scene, c.path, 1), ref, cov);
    const double err4_off = edge_error(raster(lib_, scene, c.path, 4, false), ref, cov);
    const double err4_on = edge_error(raster(lib_, scene, c.path, 4, true), ref, cov);
    std::printf("%s MASK edges: 1 sample %.4f, 4 samples without alpha to coverage %.4f, with %.4f\n",
                to_string(c.backend), err1, err4_off, err4_on);
    EXPECT_LT(err4_on, 0.75 * err4_off);
    EXPECT_LT(err4_on, 0.6 * err1);
}

// A highlight smaller than a pixel: a smooth metal sphere (roughness 0.06, alpha^2 1.3e-5) under a
// point light, about 40 pixels across, seen through 4 samples. A pixel's shading points hit or miss
// a peak hundreds of times the pixel's mean, so one sample or four are about equally wrong where
// the peak falls, and four can be much worse than one (a hit at a triangle's centroid weighs a
// quarter of the pixel). With NDF filtering (aa.specular_filter, the default) the pixels near the
// peak approach the tracer's box-filtered pixels. The peak is moved over sub-pixel positions (the
// light in small steps) and the errors summed, so that no lucky position decides.
TEST_P(AaTest, SpecularFilterGivesSubPixelHighlightsThePixelsMean) {
    const AaCase c = GetParam();
    if (c.backend == Backend::osmesa) GTEST_SKIP() << "shading only, the same shaders on both backends: the egl cases cover it";
    double e_one = 0.0, e_off = 0.0, e_on = 0.0;
    for (int k = 0; k < 5; ++k) {
        Scene scene;
        scene.source = "test:sub_pixel_highlight";
        Material metal = lambert_material("metal", glm::vec3(1.0f));
        metal.metallic = 1.0f;
        metal.roughness = 0.06f;
        scene.materials.push_back(metal);
        Primitive sphere = uv_sphere(0.5f, 24);
        sphere.material = 0;
        add_mesh_node(scene, "sphere", std::move(sphere));
        Light bulb;
        bulb.name = "bulb";
        bulb.intensity = 20.0f;
        const float t = static_cast<float>(k);
        add_light_node(scene, bulb, glm::translate(glm::mat4(1.0f), glm::vec3(1.3f + 0.031f * t, 1.1f + 0.017f * t, 1.9f)));
        add_look_at_camera(scene, {0.2f, 0.15f, 3.0f}, {0.03f, -0.02f, 0.0f}, 0.45f);
        scene.update_world_transforms();

        const Reference ref = test::trace_box_reference(lib_, scene, kSize, kSize, 8, 64, 300u + 10u * static_cast<std::uint32_t>(k));
        auto render = [&](int samples, bool filter) {
            return raster(lib_, scene, c.path, samples, true, std::string("aa.specular_filter=") + (filter ? "1" : "0"));
        };
        // The highlight: pixels within 3 of one where the reference is over 10x the sphere's median.
        std::vector<double> lit;
        for (double v : ref.mean)
            if (v > 0.0) lit.push_back(v);
        ASSERT_GT(lit.size(), 600u) << "the sphere should cover a good part of the image";
        std::nth_element(lit.begin(), lit.begin() + static_cast<long>(lit.size() / 2), lit.end());
        const double median = lit[lit.size() / 2];
        std::vector<double> mask(ref.mean.size(), 0.0);
        int peak_pixels = 0;
        for (int y = 0; y < kSize; ++y)
            for (int x = 0; x < kSize; ++x)
                if (ref.mean[static_cast<size_t>(y * kSize + x)] > 10.0 * median) {
                    ++peak_pixels;
                    for (int j = std::max(0, y - 3); j <= std::min(kSize - 1, y + 3); ++j)
                        for (int i = std::max(0, x - 3); i <= std::min(kSize - 1, x + 3); ++i) mask[static_cast<size_t>(j * kSize + i)] = 0.5;
                }
        ASSERT_GT(peak_pixels, 0) << "no highlight in the reference";
        const double one = edge_error(render(1, true), ref, mask), off = edge_error(render(4, false), ref, mask),
                     on = edge_error(render(4, true), ref, mask);
        std::printf("  light position %d: highlight RMSE 1 sample %.3f, 4 samples %.3f, with the specular filter %.3f\n", k, one, off, on);
        e_one += one * one;
        e_off += off * off;
        e_on += on * on;
    }
    e_one = std::sqrt(e_one / 5.0), e_off = std::sqrt(e_off / 5.0), e_on = std::sqrt(e_on / 5.0);
    std::printf("%s %s: highlight RMSE against the box-filtered tracer: 1 sample %.3f, 4 samples %.3f, with the specular filter %.3f\n",
                to_string(c.backend), c.path == RenderPath::forward ? "forward" : "deferred", e_one, e_off, e_on);
    EXPECT_LT(e_on, 0.9 * e_off) << "the filter must bring 4 samples closer to the box-filtered pixels";
    EXPECT_LT(e_on, 0.9 * e_one) << "with the filter, 4 samples must beat one";
}

INSTANTIATE_TEST_SUITE_P(BackendsAndPaths, AaTest,
                         ::testing::Values(AaCase{Backend::egl, RenderPath::forward}, AaCase{Backend::egl, RenderPath::deferred},
                                           AaCase{Backend::osmesa, RenderPath::forward}, AaCase{Backend::osmesa, RenderPath::deferred}),
                         [](const ::testing::TestParamInfo<AaCase>& info) {
                             return std::string(to_string(info.param.backend)) + (info.param.path == RenderPath::forward ? "_forward" : "_deferred");
                         });

}  // namespace
}  // namespace candela
