// Batch statistics (engine/image/batch_stats): per-pixel z-tests and the z of the image mean,
// on synthetic batches drawn from known distributions (seeded, so the numbers are fixed).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "core/error.hpp"
#include "image/batch_stats.hpp"

namespace candela {
namespace {

constexpr int kStatsSize = 64;

// The true value of pixel (x, y): a smooth colour ramp between 0.2 and about 2.
glm::vec3 truth(int x, int y) {
    const float u = static_cast<float>(x) / kStatsSize, v = static_cast<float>(y) / kStatsSize;
    return {0.2f + 1.8f * u, 0.3f + 1.2f * v, 0.5f + 0.5f * u * v};
}

// `count` batches whose pixels are truth * scale * (1 + global_k) + N(0, (relative_noise * truth)^2):
// global_k ~ N(0, global_noise^2) is one number per batch, shared by all its pixels (a correlated
// error such as a batch's samples of a light), the rest is independent per pixel and channel.
std::vector<ImageF> make_batches(int count, unsigned seed, double relative_noise, double scale = 1.0,
                                 double global_noise = 0.0) {
    std::mt19937 rng(seed);
    std::normal_distribution<double> normal(0.0, 1.0);
    std::vector<ImageF> batches;
    for (int k = 0; k < count; ++k) {
        ImageF im(kStatsSize, kStatsSize, 4);
        const double global = 1.0 + global_noise * normal(rng);
        for (int y = 0; y < kStatsSize; ++y)
            for (int x = 0; x < kStatsSize; ++x) {
                const glm::vec3 t = truth(x, y);
                float* p = im.at(x, y);
                for (int c = 0; c < 3; ++c)
                    p[c] = static_cast<float>(t[c] * scale * global + relative_noise * t[c] * normal(rng));
                p[3] = 4.0f;  // a sample count, as --spp-shard writes; ignored
            }
        batches.push_back(std::move(im));
    }
    return batches;
}

ImageF truth_image(double scale = 1.0) {
    ImageF im(kStatsSize, kStatsSize, 4);
    for (int y = 0; y < kStatsSize; ++y)
        for (int x = 0; x < kStatsSize; ++x) {
            const glm::vec3 t = truth(x, y);
            float* p = im.at(x, y);
            for (int c = 0; c < 3; ++c) p[c] = static_cast<float>(t[c] * scale);
            p[3] = 1.0f;
        }
    return im;
}

TEST(BatchStats, EqualMeansPassAndZOfMeanIsSmall) {
    const BatchCompareResult r = compare_batches(make_batches(16, 1, 0.1), make_batches(16, 2, 0.1));
    EXPECT_EQ(r.batches_a, 16);
    EXPECT_EQ(r.batches_b, 16);
    EXPECT_EQ(r.pixels, static_cast<std::size_t>(kStatsSize * kStatsSize));
    EXPECT_EQ(r.nonfinite_pixels, 0u);
    EXPECT_EQ(r.compared_pixels, r.pixels);
    // Normal tails at 5 sigma are 6e-7; with 16 batches a side the estimated se makes z a
    // Student t with about 30 degrees of freedom (two-sided tail 2e-5 per channel).
    EXPECT_GE(r.passing_fraction, 0.999);
    EXPECT_LT(std::fabs(r.z_of_mean), 4.0);
    for (int c = 0; c < 3; ++c) EXPECT_LT(std::fabs(r.z_of_mean_rgb[c]), 4.0);
    EXPECT_NEAR(r.mean_a, r.mean_b, 0.01 * r.mean_b);
    EXPECT_GT(r.mean_a, 0.5);  // not a black image
}

TEST(BatchStats, StandardErrorsHaveTheRightScale) {
    // At |z| < 1 a pixel passes when all three channels do: about 0.68^3 = 0.32 if the standard
    // errors are right (a t with 30 dof: 0.675^3 = 0.31). A se too large by sqrt(N) would pass
    // nearly every pixel, one too small by sqrt(N) nearly none.
    const BatchCompareResult r = compare_batches(make_batches(16, 3, 0.1), make_batches(16, 4, 0.1), 1.0);
    EXPECT_GT(r.passing_fraction, 0.27);
    EXPECT_LT(r.passing_fraction, 0.37);
    EXPECT_DOUBLE_EQ(r.z_threshold, 1.0);
    // The z of the largest magnitude per pixel is kept for a map.
    ASSERT_EQ(r.z.size(), r.pixels);
    double largest = 0;
    for (float z : r.z) largest = std::max(largest, static_cast<double>(std::fabs(z)));
    EXPECT_NEAR(largest, r.max_abs_z, 1e-6 * largest);  // r.z is float
    EXPECT_GT(largest, 2.0);
}

TEST(BatchStats, SmallBiasIsCaughtByTheZOfTheMeanNotPerPixel) {
    // B is 0.1 % brighter. Per pixel that is 0.14 standard errors (invisible); over 4096
    // pixels' mean it is about 9.
    const BatchCompareResult r = compare_batches(make_batches(16, 5, 0.02), make_batches(16, 6, 0.02, 1.001));
    EXPECT_GE(r.passing_fraction, 0.999);
    EXPECT_LT(r.z_of_mean, -4.0);
    EXPECT_NEAR(r.relative_difference, -0.001 / 1.001, 2e-4);
    // The same bias unrevealed without it: equal means stay below 4.
    const BatchCompareResult same = compare_batches(make_batches(16, 5, 0.02), make_batches(16, 6, 0.02));
    EXPECT_LT(std::fabs(same.z_of_mean), 4.0);
}

TEST(BatchStats, ZOfMeanUsesTheBatchToBatchVarianceOfTheImageMean) {
    // Each batch has a 2 % global error shared by all its pixels. The image mean's standard error
    // is then about 2 % / sqrt(16) of the mean, 13 times what the pixels' independent noise
    // (10 % / sqrt(16 * 4096)) suggests; a z computed from summed pixel variances would be that
    // much too large.
    const BatchCompareResult r =
        compare_batches(make_batches(16, 7, 0.1, 1.0, 0.02), make_batches(16, 8, 0.1, 1.0, 0.02));
    EXPECT_LT(std::fabs(r.z_of_mean), 4.0);
    const double expected_se = 0.02 * r.mean_a / 4.0;
    EXPECT_GT(r.se_mean_a, 0.5 * expected_se);
    EXPECT_LT(r.se_mean_a, 2.0 * expected_se);
    EXPECT_GT(r.se_mean_a, 5.0 * 0.1 * r.mean_a / std::sqrt(16.0 * kStatsSize * kStatsSize));
}

TEST(BatchStats, AgainstAnExactReference) {
    const std::vector<ImageF> a = make_batches(16, 9, 0.02);
    const BatchCompareResult r = compare_batches_to_reference(a, truth_image(), nullptr);
    EXPECT_EQ(r.batches_b, 0);
    EXPECT_GE(r.passing_fraction, 0.999);
    EXPECT_LT(std::fabs(r.z_of_mean), 4.0);
    EXPECT_DOUBLE_EQ(r.se_mean_b, 0.0);
    const BatchCompareResult biased = compare_batches_to_reference(a, truth_image(1.001), nullptr);
    EXPECT_LT(biased.z_of_mean, -4.0);
    EXPECT_GE(biased.passing_fraction, 0.999);
}

TEST(BatchStats, AgainstAReferenceWithItsStandardError) {
    // A stored reference: the mean and se of another batch set.
    ImageF mean, se;
    batch_mean_and_stderr(make_batches(16, 10, 0.1), mean, se);
    EXPECT_EQ(count_nonfinite(mean), 0u);
    EXPECT_EQ(count_nonfinite(se), 0u);
    const std::vector<ImageF> a = make_batches(16, 11, 0.1);
    const BatchCompareResult with_se = compare_batches_to_reference(a, mean, &se);
    EXPECT_GE(with_se.passing_fraction, 0.999);
    EXPECT_LT(std::fabs(with_se.z_of_mean), 4.0);
    EXPECT_GT(with_se.se_mean_b, 0.0);
    // Ignoring the reference's own noise halves the variance: more pixels fail at |z| < 3.
    const BatchCompareResult without_se = compare_batches_to_reference(a, mean, nullptr, 3.0);
    const BatchCompareResult with_se_3 = compare_batches_to_reference(a, mean, &se, 3.0);
    EXPECT_LT(without_se.passing_fraction, with_se_3.passing_fraction - 0.02);
}

TEST(BatchStats, MeanAndStandardErrorValues) {
    ImageF b0(1, 1, 4), b1(1, 1, 4);
    b0.pixels = {1, 2, 0, 1};
    b1.pixels = {3, 2, 4, 1};
    ImageF mean, se;
    batch_mean_and_stderr({b0, b1}, mean, se);
    EXPECT_FLOAT_EQ(mean.pixels[0], 2.0f);
    EXPECT_FLOAT_EQ(mean.pixels[1], 2.0f);
    EXPECT_FLOAT_EQ(mean.pixels[2], 2.0f);
    // s^2 = ((1-2)^2 + (3-2)^2) / (2-1) = 2; se = sqrt(2 / 2) = 1.
    EXPECT_FLOAT_EQ(se.pixels[0], 1.0f);
    EXPECT_FLOAT_EQ(se.pixels[1], 0.0f);
    EXPECT_FLOAT_EQ(se.pixels[2], 2.0f);
}

TEST(BatchStats, ZeroVarianceAndNonFinitePixels) {
    // 3 pixels: equal constants (pass), different constants (fail, infinite z), a NaN (left out).
    auto batch = [](float second, float third) {
        ImageF im(3, 1, 4);
        im.pixels = {0.5f, 0.5f, 0.5f, 1, second, second, second, 1, third, 0, 0, 1};
        return im;
    };
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const BatchCompareResult r = compare_batches({batch(1, 1), batch(1, nan), batch(1, 1)}, {batch(2, 1), batch(2, 1)});
    EXPECT_EQ(r.nonfinite_pixels, 1u);
    EXPECT_EQ(r.compared_pixels, 2u);
    EXPECT_EQ(r.passing_pixels, 1u);
    EXPECT_DOUBLE_EQ(r.passing_fraction, 0.5);
    EXPECT_TRUE(std::isinf(r.max_abs_z));
    EXPECT_FLOAT_EQ(r.z[0], 0.0f);
    EXPECT_TRUE(std::isinf(r.z[1]) && r.z[1] < 0);
    EXPECT_FLOAT_EQ(r.z[2], 0.0f);
    EXPECT_TRUE(std::isfinite(r.mean_a) && std::isfinite(r.mean_b));
    EXPECT_TRUE(std::isinf(r.z_of_mean) && r.z_of_mean < 0);  // every batch's mean is the same
}

TEST(BatchStats, BadInput) {
    const std::vector<ImageF> two = make_batches(2, 12, 0.1);
    const std::vector<ImageF> one(1, two[0]);
    try {
        compare_batches(one, two);
        FAIL() << "one batch accepted";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ExitCode::bad_input);
        EXPECT_NE(std::string(e.what()).find("at least 2"), std::string::npos) << e.what();
    }
    std::vector<ImageF> mixed = two;
    mixed[1] = ImageF(8, 8, 4);
    EXPECT_THROW(compare_batches(two, mixed), Error);
    EXPECT_THROW(compare_batches_to_reference(two, ImageF(8, 8, 4), nullptr), Error);
    const ImageF small_se(8, 8, 4);
    EXPECT_THROW(compare_batches_to_reference(two, truth_image(), &small_se), Error);
}

}  // namespace
}  // namespace candela
