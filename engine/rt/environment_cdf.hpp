#pragma once
// The environment map's importance sampling tables, built on the CPU and read by the tracer's
// shaders (environment light sampling).
#include <vector>

#include "image/image.hpp"

namespace candela::rt {

// The environment map's sampling distribution: [0, W*H) the probability of each texel
// (luminance * sin(theta), normalised), then W*H row-conditional CDFs, then the H-entry marginal
// CDF over rows (Pharr, Jakob & Humphreys, PBRT 3rd ed., 13.6.7 and 14.2.4).
std::vector<float> environment_distribution(const ImageF& equirect);

}  // namespace candela::rt
