#include <gtest/gtest.h>

#include <cmath>

#include "core/error.hpp"
#include "gltf_builder.hpp"
#include "image/image.hpp"

namespace candela {
namespace {

TEST(ToneMapping, SrgbCurveKnownValues) {
    EXPECT_FLOAT_EQ(linear_to_srgb(0.0f), 0.0f);
    EXPECT_NEAR(linear_to_srgb(1.0f), 1.0f, 1e-6f);
    EXPECT_NEAR(linear_to_srgb(0.5f), 0.735357f, 1e-5f);
    EXPECT_NEAR(linear_to_srgb(0.002f), 0.002f * 12.92f, 1e-7f);  // linear toe
}

TEST(ToneMapping, AcesIsMonotoneAndBounded) {
    float previous = -1.0f;
    for (float x = 0.0f; x < 100.0f; x = x * 1.3f + 0.001f) {
        const float y = aces_fit(glm::vec3(x)).x;
        EXPECT_GE(y, previous);
        EXPECT_LE(y, 1.0f);
        previous = y;
    }
    EXPECT_FLOAT_EQ(aces_fit(glm::vec3(0.0f)).x, 0.0f);
    EXPECT_NEAR(aces_fit(glm::vec3(1e6f)).x, 1.0f, 1e-6f);
}

TEST(ToneMapping, ExposureIsOneStopPerEv) {
    const glm::vec3 a = display_transform(glm::vec3(0.25f), 1.0f);
    const glm::vec3 b = display_transform(glm::vec3(0.5f), 0.0f);
    EXPECT_FLOAT_EQ(a.x, b.x);
    EXPECT_FLOAT_EQ(display_transform(glm::vec3(-5.0f), 0.0f).x, 0.0f);  // negative radiance clamps
}

TEST(ImageCompare, MetricsAndFailingPixels) {
    ImageF a(4, 4, 4), b(4, 4, 4);
    EXPECT_EQ(compare(a, b, 0.0).failing_pixels, 0u);
    EXPECT_TRUE(std::isinf(compare(a, b, 0.0).psnr));
    b.at(1, 2)[1] = 0.1f;
    const CompareResult r = compare(a, b, 0.05);
    EXPECT_EQ(r.failing_pixels, 1u);
    EXPECT_NEAR(r.max_abs, 0.1, 1e-7);
    EXPECT_NEAR(r.rmse, std::sqrt(0.01 / 48.0), 1e-7);
    EXPECT_NEAR(r.failing_fraction, 1.0 / 16.0, 1e-12);
    EXPECT_EQ(compare(a, b, 0.2).failing_pixels, 0u);
    ImageF small(2, 2, 4);
    EXPECT_THROW(compare(a, small, 0.1), Error);
}

TEST(ImageCompare, NonFiniteIsCountedAndFails) {
    ImageF a(2, 2, 4), b(2, 2, 4);
    a.at(0, 0)[0] = NAN;
    a.at(1, 1)[2] = INFINITY;
    EXPECT_EQ(count_nonfinite(a), 2u);
    const CompareResult r = compare(a, b, 1.0);
    EXPECT_EQ(r.nonfinite, 2u);
    EXPECT_EQ(r.failing_pixels, 2u);
}

TEST(ImageCompare, HeatmapIsBlackWhereEqualAndRedAtScale) {
    ImageF a(2, 1, 4), b(2, 1, 4);
    a.at(1, 0)[0] = 1.0f;
    const ImageF h = heatmap(a, b, 1.0);
    EXPECT_FLOAT_EQ(h.at(0, 0)[0] + h.at(0, 0)[1] + h.at(0, 0)[2], 0.0f);
    EXPECT_FLOAT_EQ(h.at(1, 0)[0], 1.0f);
    EXPECT_FLOAT_EQ(h.at(1, 0)[1], 0.0f);
}

// A known bias under reference noise of growing size: the noise-free error stays at the bias
// (within its sampling error) while the naive one grows with the noise, and naive^2 is close
// to rms^2 + ref_noise^2.
TEST(ImageCompare, BlockBiasTakesTheReferenceNoiseOut) {
    const int w = 320, h = 180;
    const float mu = 0.3f, bias = 0.01f;
    std::uint32_t state = 12345u;
    auto gauss = [&state]() {  // Box-Muller on a xorshift
        auto u = [&state]() {
            state ^= state << 13, state ^= state >> 17, state ^= state << 5;
            return (static_cast<double>(state) + 0.5) / 4294967296.0;
        };
        return static_cast<float>(std::sqrt(-2.0 * std::log(u())) * std::cos(6.283185307179586 * u()));
    };
    // Per 4x4 block each reference's mean has the noise sigma / 4; the cross product's mean over
    // 3600 x 3 blocks has a standard error of about its square over sqrt(10800).
    auto cross_se = [](double sigma, double slope) { return std::pow(sigma * slope / 4.0, 2) / std::sqrt(10800.0) + 1e-12; };
    ImageF a(w, h, 3);
    for (float& v : a.pixels) v = mu + bias;
    const float at = mu + bias;  // the slope is taken at the raster's value
    const double slope = (display_transform(glm::vec3(at + 1e-4f), 0.0f).x - display_transform(glm::vec3(at - 1e-4f), 0.0f).x) / 2e-4;
    const double expected = bias * slope;
    double previous_naive = 0;
    for (const float sigma : {0.0f, 0.05f, 0.2f, 0.4f}) {
        ImageF r1(w, h, 3), r2(w, h, 3);
        for (float& v : r1.pixels) v = mu + sigma * gauss();
        for (float& v : r2.pixels) v = mu + sigma * gauss();
        const BlockBias b = block_bias(a, r1, r2, 4);
        const double se2 = cross_se(sigma, slope);
        EXPECT_NEAR(b.rms * b.rms, expected * expected, 4.0 * se2 + 1e-2 * expected * expected) << "sigma " << sigma;
        EXPECT_NEAR(b.naive_rms * b.naive_rms, b.rms * b.rms + b.ref_noise_rms * b.ref_noise_rms, 8.0 * se2 + 1e-9) << "sigma " << sigma;
        EXPECT_GE(b.naive_rms, previous_naive) << "sigma " << sigma;
        previous_naive = b.naive_rms;
    }
    EXPECT_GT(previous_naive, 2.0 * expected);  // the naive error is mostly noise at the largest sigma
    // A raster equal to the expected value: no error, however noisy the reference.
    ImageF exact(w, h, 3), r1(w, h, 3), r2(w, h, 3);
    for (float& v : exact.pixels) v = mu;
    for (float& v : r1.pixels) v = mu + 0.2f * gauss();
    for (float& v : r2.pixels) v = mu + 0.2f * gauss();
    EXPECT_LT(std::pow(block_bias(exact, r1, r2, 4).rms, 2), 4.0 * cross_se(0.2, slope));
    EXPECT_GT(block_bias(exact, r1, r2, 4).naive_rms, 2.0 * expected);
    EXPECT_THROW(block_bias(a, r1, ImageF(w, h - 1, 3), 4), Error);
}

TEST(ImageIO, ExrRoundTripKeepsLinearFloats) {
    const auto dir = test::test_dir("imageio");
    ImageF img(3, 2, 4);
    img.at(2, 1)[0] = 123.456f;
    img.at(0, 0)[1] = 1e-4f;
    write_image(dir / "x.exr", img);
    const ImageF back = read_image(dir / "x.exr");
    ASSERT_EQ(back.width, 3);
    EXPECT_FLOAT_EQ(back.at(2, 1)[0], 123.456f);
    EXPECT_FLOAT_EQ(back.at(0, 0)[1], 1e-4f);
}

TEST(ImageIO, PngIsDisplayTransformed) {
    const auto dir = test::test_dir("imageio_png");
    ImageF img(1, 1, 4);
    img.at(0, 0)[0] = img.at(0, 0)[1] = img.at(0, 0)[2] = 0.18f;
    write_image(dir / "x.png", img, 0.0f);
    const ImageF back = read_image(dir / "x.png");
    const float expected = display_transform(glm::vec3(0.18f), 0.0f).x;
    EXPECT_NEAR(back.at(0, 0)[0], expected, 0.5f / 255.0f + 1e-6f);
}

TEST(ImageIO, BadPathsAreBadInput) {
    ImageF img(1, 1, 4);
    EXPECT_THROW(write_image("/nonexistent-dir/x.png", img), Error);
    EXPECT_THROW(write_image("x.unknown", img), Error);
    EXPECT_THROW(read_image("/nonexistent.png"), Error);
}

}  // namespace
}  // namespace candela
