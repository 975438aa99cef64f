// RSM indirect light judged against the ray tracer's `indirect` mode (one diffuse bounce): colour
// bleeds from the red wall onto the white floor, the error against the reference falls as the
// sample count grows, and both render paths agree.
#include <gtest/gtest.h>

#include <cmath>

#include "reference_fixture.hpp"
#include "scene/gltf_loader.hpp"

namespace candela {
namespace {
namespace fs = std::filesystem;

class RsmTest : public test::ReferenceTest {
protected:
    ImageF indirect(int w, int h, const std::vector<std::string>& knobs) {
        return raster(cornell_, w, h, settings("shadows,rsm", knobs));
    }
    ImageF traced_indirect(int w, int h, int spp) {
        rt::Options o;
        o.mode = rt::Mode::indirect;
        o.spp = spp;
        return traced(cornell_, w, h, o).image;
    }
    Scene cornell_ = load_gltf(fs::path(CANDELA_SOURCE_DIR) / "samples" / "scenes" / "cornell_point.gltf");
};


TEST_P(RsmTest, FloorNextToTheRedWallGetsRedder) {
    const int n = 96;
    const ImageF off = raster(cornell_, n, n, settings("shadows", {}));
    const ImageF on = raster(cornell_, n, n, settings("shadows,rsm", {}));
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
    const ImageF reference = traced_indirect(n, n, 256);
    double last = 1e30;
    for (int samples : {8, 32, 128}) {
        SCOPED_TRACE(samples);
        const double e = rmse(indirect(n, n, {"debug.view=indirect", "rsm.samples=" + std::to_string(samples)}), reference);
        std::printf("rsm samples %d: rmse %.4f against --raytrace indirect\n", samples, e);
        EXPECT_LT(e, last);
        last = e;
    }
    // Default settings: within the bound below.
    const double e = rmse(indirect(n, n, {"debug.view=indirect"}), reference);
    std::printf("rsm defaults: rmse %.4f\n", e);
    EXPECT_LT(e, 0.09);
}

TEST_P(RsmTest, ForwardAndDeferredGatherTheSameLight) {
    const ImageF fwd = indirect(48, 48, {"debug.view=indirect", "render.path=forward"});
    const ImageF def = indirect(48, 48, {"debug.view=indirect", "render.path=deferred"});
    EXPECT_LT(rmse(fwd, def), 2e-3);
}

INSTANTIATE_TEST_SUITE_P(Backends, RsmTest, ::testing::Values(Backend::egl), test::backend_name);

}  // namespace
}  // namespace candela
