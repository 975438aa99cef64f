// RSM for area lights: the Cornell box lit only by its emissive ceiling quad bounces
// light through the reflective shadow maps of the quad's shadowed pieces. Judged against the ray
// tracer's `indirect` mode (exactly one diffuse bounce) at low spp:
// - the ceiling beside the light gets no direct light (the quad emits downwards), so whatever
//   RSM adds there is indirect light, and it must be there;
// - the image mean of (RSM on - RSM off) must be close to the tracer's indirect mean: within
//   35 % of the tracer with occlusion (RSM ignores occlusion between the bounce point and the
//   receiver: +13 % on this box) and within 15 % of the tracer without it (RSM's own model);
// - the flux of pieces without RSM views is carried by those with (rsm.area_pieces).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "reference_fixture.hpp"
#include "scene/gltf_loader.hpp"

namespace candela {
namespace {
namespace fs = std::filesystem;

constexpr int kSize = 64;

double luminance(const float* p) { return 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]; }

// Mean luminance of a - b (b may be null) over the pixels with x0 <= x < x1, y0 <= y < y1.
double region_mean(const ImageF& a, const ImageF* b, int x0, int x1, int y0, int y1) {
    double sum = 0.0;
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) sum += luminance(a.at(x, y)) - (b ? luminance(b->at(x, y)) : 0.0);
    return sum / ((x1 - x0) * (y1 - y0));
}
double image_mean(const ImageF& a, const ImageF* b = nullptr) { return region_mean(a, b, 0, a.width, 0, a.height); }

class RsmAreaTest : public test::ReferenceTest {
protected:
    ImageF raster_box(const std::string& effects, std::vector<std::string> knobs = {}) {
        return raster(box_, kSize, kSize, settings(effects, knobs));
    }
    ImageF traced_indirect(bool occlusion, int spp) {
        rt::Options o;
        o.mode = rt::Mode::indirect;
        o.spp = spp;
        o.indirect_occlusion = occlusion;
        return traced(box_, kSize, kSize, o).image;
    }
    // The ceiling left and right of the light (camera_front at 64x64: rows 0-7 are ceiling, the
    // quad covers columns 25-38 of rows 5-7; the side walls start below row 3 at the edges).
    double ceiling(const ImageF& a, const ImageF* b = nullptr) const {
        const int w = a.width, h = a.height;
        return 0.5 * (region_mean(a, b, w / 6, w * 35 / 100, 0, h / 8) + region_mean(a, b, w * 65 / 100, w * 5 / 6, 0, h / 8));
    }
    Scene box_ = load_gltf(fs::path(CANDELA_SOURCE_DIR) / "samples" / "scenes" / "cornell_box.gltf");
};

TEST_P(RsmAreaTest, CeilingBesideTheLightIsLitIndirectly) {
    const ImageF off = raster_box("shadows");
    const ImageF on = raster_box("shadows,rsm");
    const ImageF ref = traced_indirect(true, 16);
    const double dark = ceiling(off), added = ceiling(on, &off), exact = ceiling(ref);
    std::printf("ceiling beside the light: %.5f without RSM, +%.5f with it; tracer indirect %.5f\n", dark, added, exact);
    // The setting of the test: no direct light reaches this ceiling, the tracer sees indirect light there.
    EXPECT_LT(dark, 1e-4);
    ASSERT_GT(exact, 5e-3);
    // RSM supplies it (half to twice the one-bounce reference: sampled gather, no occlusion).
    EXPECT_GT(added, 0.5 * exact);
    EXPECT_LT(added, 2.0 * exact);
    // RSM only adds light: no pixel gets darker.
    int darker = 0;
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) darker += luminance(on.at(x, y)) < luminance(off.at(x, y)) - 1e-5;
    EXPECT_EQ(darker, 0);
    EXPECT_EQ(count_nonfinite(on), 0u);
}

// The tolerances. The tracer's image mean at 64x64 x 16 spp (65536 paths) has a standard error
// of about 1 % with occlusion (four seeds: 0.02313..0.02383) and, sampling bounce points by area,
// about 3 % without it at 32 spp (16 spp, four seeds: 0.02578..0.02740). RSM's mean moves by about 3 %
// with the image size (its gather is a per-pixel sampled estimate: 64x64 0.02577, 96x96 0.02713,
// 128x128 0.02617). RSM leaves out occlusion between the bounce point and the receiver, which is
// +13 % on this box (the tracer with and without it, 256x256 x 64 spp: 0.02357 and 0.02658).
// So: against the tracer's own model (no occlusion) within 15 % (about 5 standard errors of the
// two estimates together); against the exact one bounce within 35 %, room for the +13 % model
// error and the noise. A wrong flux scale (a factor pi, 2 for the hemisphere, or the pieces
// counted once each instead of sharing the emitter's power: 4) fails both.
TEST_P(RsmAreaTest, AddedLightMatchesTheTracersOneBounceMean) {
    const ImageF off = raster_box("shadows");
    const ImageF on = raster_box("shadows,rsm");
    const double rsm = image_mean(on, &off);
    const double exact = image_mean(traced_indirect(true, 16));
    const double own_model = image_mean(traced_indirect(false, 32));
    std::printf("image mean of RSM on - off %.5f; tracer indirect %.5f (RSM/tracer %.3f), without occlusion %.5f (%.3f)\n", rsm,
                exact, rsm / exact, own_model, rsm / own_model);
    ASSERT_GT(exact, 0.0);
    EXPECT_NEAR(rsm / exact, 1.0, 0.35);
    EXPECT_NEAR(rsm / own_model, 1.0, 0.15);
}

// Eight pieces per emitter but RSM views for only two: their flux carries the emitter's power
// (rsm.frag's flux scale), so the added light stays the same up to where the two sit and the
// gather's noise (many samples and a full-resolution gather keep that small: at 128x128 with
// default sampling, 8, 4, 2, 1 pieces gave 0.02571, 0.02603, 0.02648, 0.02634). Without the
// scale, two of eight would give a quarter.
TEST_P(RsmAreaTest, FewerRsmPiecesCarryTheWholeEmitter) {
    const std::vector<std::string> knobs = {"arealight.samples=8", "rsm.samples=256", "rsm.gather=full"};
    auto with = [&](const char* extra) {
        std::vector<std::string> k = knobs;
        k.push_back(extra);
        return k;
    };
    const ImageF off = raster_box("shadows", knobs);
    const double all = image_mean(raster_box("shadows,rsm", with("rsm.area_pieces=8")), &off);
    const double two = image_mean(raster_box("shadows,rsm", with("rsm.area_pieces=2")), &off);
    std::printf("added light with 8 of 8 pieces %.5f, 2 of 8 %.5f (ratio %.3f)\n", all, two, two / all);
    ASSERT_GT(all, 0.0);
    EXPECT_NEAR(two / all, 1.0, 0.15);
}

INSTANTIATE_TEST_SUITE_P(Backends, RsmAreaTest, ::testing::Values(Backend::egl), test::backend_name);

}  // namespace
}  // namespace candela
