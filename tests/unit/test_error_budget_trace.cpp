// The tracer rung of error-budgeted rendering (engine/accuracy/error_budget_measure.hpp): its
// noise estimate, read from two independent halves while it traces, is what the promise rests on.
// - Calibration: against a converged image (a reference of 4x the last round's samples), the rung's block
//   error is its noise estimate combined with the reference's own, on a sample scene and on
//   random scenes nobody wrote, at every round.
// - The estimate falls as the samples double (as 1/sqrt(spp)), and trace_within stops at the
//   first round whose estimate is within half the budget: a larger budget's image is a prefix of
//   a smaller budget's run.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "accuracy/error_budget_measure.hpp"
#include "gl_fixture.hpp"
#include "scene/generate.hpp"
#include "scene/gltf_loader.hpp"

namespace candela::budget {
namespace {
namespace fs = std::filesystem;

constexpr int kW = 48, kH = 36;

class TraceRungTest : public test::GlContextTest {
protected:
    ShaderLibrary lib_{fs::path(CANDELA_SOURCE_DIR) / "shaders"};
    static Camera camera_of(const Scene& scene) { return scene.select_camera("", static_cast<float>(kW) / kH); }
};

// After each of three rounds (64, 128, 256 spp) the block error against a 1024-spp reference is
// sqrt(noise^2 + reference noise^2) up to the estimate's own scatter: mean absolute block
// differences of independent, roughly normal noises add in quadrature. The bounds (x0.6 to x1.6)
// are wide against that scatter (some hundred blocks per image) and narrow against the failures
// that matter: a noise estimate off by a factor of two (a half counted twice, correlated halves,
// the wrong scale between the halves' difference and the mean's error).
TEST_P(TraceRungTest, NoiseEstimateIsTheErrorAgainstAConvergedImage) {
    std::vector<std::pair<std::string, Scene>> scenes;
    scenes.emplace_back("cornell_box", load_gltf(fs::path(CANDELA_SOURCE_DIR) / "samples" / "scenes" / "cornell_box.gltf"));
    for (std::uint32_t seed : {3u, 17u}) scenes.emplace_back("random " + std::to_string(seed), make_random_scene(seed));
    for (const auto& [name, scene] : scenes) {
        SCOPED_TRACE(name);
        const Camera camera = camera_of(scene);
        const Reference ref = path_reference(scene, lib_, camera, kW, kH, 1024);
        ASSERT_EQ(ref.nonfinite_samples, 0u);
        TraceRung rung(scene, lib_, camera, kW, kH);
        double last_noise = 0;
        for (int round = 0; round < 3; ++round) {
            rung.step();
            const ImageF image = rung.image();
            ASSERT_EQ(count_nonfinite(image), 0u);
            const double error = block_error(image, ref.image);
            const double expected = std::sqrt(rung.noise() * rung.noise() + ref.noise * ref.noise);
            std::printf("%s: %d spp, noise estimate %.5f, reference noise %.5f, error %.5f (x%.2f of expected)\n", name.c_str(), rung.spp(),
                        rung.noise(), ref.noise, error, error / expected);
            EXPECT_EQ(rung.spp(), 64 << round);
            EXPECT_GT(rung.noise(), 0.0);
            EXPECT_GT(error, 0.6 * expected);
            EXPECT_LT(error, 1.6 * expected);
            if (round > 0) {  // doubling the samples: noise x1/sqrt(2), up to the estimate's scatter
                EXPECT_GT(rung.noise() / last_noise, 0.5);
                EXPECT_LT(rung.noise() / last_noise, 0.9);
            }
            last_noise = rung.noise();
        }
        EXPECT_EQ(rung.nonfinite_samples(), 0u);
    }
}

TEST_P(TraceRungTest, StopsAtTheFirstRoundWithinHalfTheBudget) {
    const Scene scene = make_random_scene(5);
    const Camera camera = camera_of(scene);
    TraceRung rung(scene, lib_, camera, kW, kH);
    rung.step();
    rung.step();  // 128 spp
    const double noise = rung.noise();
    // A budget whose target lies between the first and the second round's estimates stops at the second.
    TraceRung first(scene, lib_, camera, kW, kH);
    first.step();
    ASSERT_GT(first.noise(), noise);
    const double budget = (noise + 0.5 * (first.noise() - noise)) / kTraceNoiseShare;
    const Traced t = trace_within(scene, lib_, camera, kW, kH, budget);
    EXPECT_TRUE(t.within);
    EXPECT_EQ(t.spp, 128);
    EXPECT_EQ(t.noise, noise);
    const ImageF expected = rung.image();
    ASSERT_EQ(t.image.pixels.size(), expected.pixels.size());
    EXPECT_EQ(t.image.pixels, expected.pixels);  // deterministic: the same seeds per round
    // A budget no sample count reaches stops at the limit, and says so.
    const Traced capped = trace_within(scene, lib_, camera, 8, 6, 1e-7);
    EXPECT_FALSE(capped.within);
    EXPECT_EQ(capped.spp, kTraceMaxSpp);
}

INSTANTIATE_TEST_SUITE_P(Backends, TraceRungTest, ::testing::Values(Backend::egl), test::backend_name);

}  // namespace
}  // namespace candela::budget
