#pragma once
// Statistics of independent batches of a noisy image (e.g. `candela render --raytrace ...
// --spp-shard K/N` outputs, one image per K): per-pixel z-tests and the z of the image mean,
// the checks `candela compare --batches` prints and the tracer's statistical tests assert.
//
// Conventions (chosen so that the numbers answer "are these two renders of the same scene
// the same in expectation?"):
// - Batches of a set are equally weighted, independent and identically distributed: render
//   them with the same sample count each (--spp a multiple of N). The alpha channel is ignored.
// - Per pixel and per RGB channel: mean over the N batches and the standard error of that mean,
//   se^2 = s^2 / N with s^2 the unbiased sample variance over the batches (divisor N - 1).
// - Per-pixel test, per channel: z = (mean_A - mean_B) / sqrt(se_A^2 + se_B^2). A pixel passes
//   when all three channels have |z| < threshold. Where the combined standard error is 0 (e.g. a
//   background pixel that every sample sees alike) the channel passes only if the means are
//   exactly equal. With few batches the standard errors are themselves noisy, so z has heavier
//   tails than a normal variable (Student's t with about 2N - 2 degrees of freedom).
// - z of the image mean: the image mean (over the compared pixels) is a sum of correlated pixel
//   values (a batch's pixels share samples of the light, the sky...), so its variance is NOT the
//   sum of the pixel variances. It is estimated the same way as a pixel's: each batch's image
//   mean, then the standard error of those N numbers. z = (mean_A - mean_B) /
//   sqrt(se_A^2 + se_B^2). It is reported on luminance (Rec. 709 weights 0.2126, 0.7152, 0.0722)
//   and per channel.
// - A reference image R instead of set B: its pixels are the means; an optional standard-error
//   image gives their se (RGB), else 0. Its image mean's variance is then taken as
//   sum(se^2) / pixels^2, i.e. its pixels are assumed independent (the only assumption possible
//   from one se image; it understates that variance if the reference's pixels are correlated).
// - Pixels where any image (any batch, the reference or its se image) has a non-finite RGB value
//   are left out of every statistic and counted.
#include <cstddef>
#include <vector>

#include <glm/glm.hpp>

#include "image/image.hpp"

namespace candela {

// The mean of N independent batch values (N >= 2) and the standard error of that mean,
// sqrt(s^2 / N) with s^2 the unbiased sample variance: the statistics of one number measured per
// batch (an image mean, a moment of a blur), as the tests of the tracer use them.
struct BatchMean {
    double mean = 0.0, se = 0.0;
};
BatchMean batch_mean(const std::vector<double>& values);

struct BatchCompareResult {
    int batches_a = 0;
    int batches_b = 0;               // 0 when B is a reference image
    std::size_t pixels = 0;          // width * height
    std::size_t nonfinite_pixels = 0;  // left out (non-finite RGB somewhere)
    std::size_t compared_pixels = 0;   // pixels - nonfinite_pixels
    std::size_t passing_pixels = 0;    // all RGB channels with |z| < z_threshold
    double passing_fraction = 0;       // passing / compared (1 when nothing is compared)
    double z_threshold = 5;
    double max_abs_z = 0;              // largest per-channel |z| (may be infinite)
    // Image means over the compared pixels, luminance and RGB.
    double mean_a = 0, mean_b = 0;
    glm::dvec3 mean_a_rgb{0.0}, mean_b_rgb{0.0};
    double se_mean_a = 0, se_mean_b = 0;  // standard errors of mean_a, mean_b
    double relative_difference = 0;      // (mean_a - mean_b) / mean_b (0 if mean_b is 0)
    double z_of_mean = 0;                 // luminance; +-infinity if the difference has se 0
    glm::dvec3 z_of_mean_rgb{0.0};
    // Per pixel, the channel z of largest magnitude (signed); 0 where left out.
    std::vector<float> z;
};

// Two batch sets of the same scene, each of at least 2 images of one size (throws bad_input).
BatchCompareResult compare_batches(const std::vector<ImageF>& a, const std::vector<ImageF>& b, double z_threshold = 5.0);

// A batch set (at least 2) against a reference image R with an optional standard-error image
// (nullptr: R is taken as exact). Sizes must match (throws bad_input).
BatchCompareResult compare_batches_to_reference(const std::vector<ImageF>& a, const ImageF& reference,
                                                const ImageF* reference_stderr, double z_threshold = 5.0);

// The per-pixel mean of a batch set and the standard error of that mean (RGB; alpha 1), e.g. to
// store a reference with its se image for later `compare --against REF --ref-stderr SE`.
void batch_mean_and_stderr(const std::vector<ImageF>& batches, ImageF& mean, ImageF& stderr_image);

}  // namespace candela
