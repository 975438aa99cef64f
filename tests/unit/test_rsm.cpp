// RSM indirect light judged against the ray tracer's `indirect` mode (one diffuse bounce): colour
// bleeds from the red wall onto the white floor, the error against the reference falls as the
// sample count grows, and both render paths agree.
#include <gtest/gtest.h>

#include <cmath>

#include "gl_fixture.hpp"
#include "render/renderer.hpp"
#include "rt/ray_tracer.hpp"
#include "scene/gltf_loader.hpp"

namespace candela {
namespace {
namespace fs = std::filesystem;

class RsmTest : public test::GlContextTest {
protected:
    ImageF raster(const Scene& scene, int w, int h, const std::vector<std::string>& knobs) {
        GpuScene gpu(scene);
        RenderSettings s;
        apply_effects(s, "shadows,rsm");
        for (const auto& k : knobs) apply_knob(s, k);
        Renderer renderer(lib_, scene, gpu, s);
        renderer.render(scene.select_camera("", static_cast<float>(w) / static_cast<float>(h)), w, h);
        ImageF img = renderer.read_radiance();
        EXPECT_EQ(count_nonfinite(img), 0u);
        return img;
    }
    ImageF traced(const Scene& scene, int w, int h, int spp, bool occlusion) {
        GpuScene gpu(scene);
        rt::Options o;
        o.mode = rt::Mode::indirect;
        o.spp = spp;
        o.indirect_occlusion = occlusion;
        rt::RayTracer tracer(lib_, scene, gpu, o);
        rt::Result r = tracer.render(scene.select_camera("", static_cast<float>(w) / static_cast<float>(h)), w, h);
        EXPECT_EQ(count_nonfinite(r.image), 0u);
        return r.image;
    }
    ShaderLibrary lib_{fs::path(CANDELA_SOURCE_DIR) / "shaders"};
    Scene cornell_ = load_gltf(fs::path(CANDELA_SOURCE_DIR) / "samples" / "scenes" / "cornell_point.gltf");
};

double rmse(const ImageF& a, const ImageF& b) {
    double sum = 0.0;
    for (int y = 0; y < a.height; ++y)
        for (int x = 0; x < a.width; ++x)
            for (int c = 0; c < 3; ++c) {
                const double d = a.at(x, y)[c] - b.at(x, y)[c];
                sum += d * d;
            }
    return std::sqrt(sum / (a.width * a.height * 3));
}

TEST_P(RsmTest, FloorNextToTheRedWallGetsRedder) {
    const int n = 96;
    GpuScene gpu(cornell_);
    RenderSettings s;
    apply_effects(s, "shadows");
    auto render = [&](const RenderSettings& settings) {
        Renderer renderer(lib_, cornell_, gpu, settings);
        renderer.render(cornell_.select_camera("", 1.0f), n, n);
        return renderer.read_radiance();
    };
    const ImageF off = render(s);
    apply_effects(s, "shadows,rsm");
    const ImageF on = render(s);
    EXPECT_EQ(count_nonfinite(on), 0u);
    // The floor's left edge, by the red wall: the bottom rows, the left fifth of the image.
    auto red_over_green = [&](const ImageF& img) {
        double r = 0.0, g = 0.0;
        for (int y = n - 8; y < n - 2; ++y)
            for (int x = n / 8; x < n / 4; ++x) {
                r += img.at(x, y)[0];
                g += img.at(x, y)[1];
            }
        return r / g;
    };
    const double before = red_over_green(off), after = red_over_green(on);
    std::printf("floor by the red wall: R/G %.3f without RSM, %.3f with\n", before, after);
    EXPECT_GT(after, before * 1.05);
}

TEST_P(RsmTest, ErrorAgainstRayTracedIndirectFallsWithSamples) {
    const int n = 64;
    const ImageF reference = traced(cornell_, n, n, 256, true);
    double last = 1e30;
    for (int samples : {8, 32, 128}) {
        SCOPED_TRACE(samples);
        const double e = rmse(raster(cornell_, n, n, {"debug.view=indirect", "rsm.samples=" + std::to_string(samples)}), reference);
        std::printf("rsm samples %d: rmse %.4f against --raytrace indirect\n", samples, e);
        EXPECT_LT(e, last);
        last = e;
    }
    // Default settings: within the stated bound (README, issue 6 note).
    const double e = rmse(raster(cornell_, n, n, {"debug.view=indirect"}), reference);
    std::printf("rsm defaults: rmse %.4f\n", e);
    EXPECT_LT(e, 0.09);
}

TEST_P(RsmTest, ForwardAndDeferredGatherTheSameLight) {
    const ImageF fwd = raster(cornell_, 48, 48, {"debug.view=indirect", "render.path=forward"});
    const ImageF def = raster(cornell_, 48, 48, {"debug.view=indirect", "render.path=deferred"});
    EXPECT_LT(rmse(fwd, def), 2e-3);
}

INSTANTIATE_TEST_SUITE_P(Backends, RsmTest, ::testing::Values(Backend::egl), test::backend_name);

}  // namespace
}  // namespace candela
