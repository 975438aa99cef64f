#pragma once
// The tracer's statistical tests against closed forms: independent batches of one render judged
// per pixel and channel (|z| < kPixelZ for kPassRate of them) and by the z of the image mean per
// channel (|z| < kMeanZ), with the closed form's own numerical error taken as 1e-6 of its mean
// (its float storage and quadrature; without it a pixel whose samples all agree, se 0, would have
// to equal the closed form to the last bit).
#include <algorithm>
#include <cmath>
#include <vector>

#include "image/batch_stats.hpp"
#include "image/image.hpp"

namespace candela::test {

constexpr double kPixelZ = 5.0;
constexpr double kMeanZ = 4.0;
constexpr double kPassRate = 0.9975;

inline BatchCompareResult judge_against_closed_form(const std::vector<ImageF>& batches, const ImageF& reference) {
    double mean = 0.0;
    for (size_t i = 0; i < reference.pixels.size(); ++i)
        if (i % 4 != 3) mean += std::fabs(reference.pixels[i]) / (3.0 * reference.width * reference.height);
    ImageF se(reference.width, reference.height, 4);
    for (float& s : se.pixels) s = static_cast<float>(1e-6 * mean);
    return compare_batches_to_reference(batches, reference, &se, kPixelZ);
}

inline double worst_mean_z(const BatchCompareResult& r) {
    return std::max({std::fabs(r.z_of_mean_rgb.x), std::fabs(r.z_of_mean_rgb.y), std::fabs(r.z_of_mean_rgb.z)});
}

inline bool passes_closed_form(const BatchCompareResult& r) { return r.passing_fraction >= kPassRate && worst_mean_z(r) < kMeanZ; }

}  // namespace candela::test
