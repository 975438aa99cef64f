#include "rt/environment_cdf.hpp"

#include <algorithm>
#include <cmath>

namespace candela::rt {

std::vector<float> environment_distribution(const ImageF& map) {
    const int w = map.width, h = map.height;
    const size_t n = static_cast<size_t>(w) * static_cast<size_t>(h);
    std::vector<float> out(2 * n + static_cast<size_t>(h), 0.0f);
    std::vector<double> f(n);
    std::vector<double> row_sum(static_cast<size_t>(h), 0.0);
    double total = 0.0;
    for (int y = 0; y < h; ++y) {
        const double sin_theta = std::sin(3.14159265358979 * (y + 0.5) / h);
        for (int x = 0; x < w; ++x) {
            const float* p = map.at(x, y);
            double lum = 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
            if (!std::isfinite(lum) || lum < 0.0) lum = 0.0;
            const size_t i = static_cast<size_t>(y) * static_cast<size_t>(w) + static_cast<size_t>(x);
            f[i] = lum * sin_theta;
            row_sum[static_cast<size_t>(y)] += f[i];
        }
        total += row_sum[static_cast<size_t>(y)];
    }
    if (!(total > 0.0)) {  // a black map: sample uniformly
        std::fill(f.begin(), f.end(), 1.0);
        std::fill(row_sum.begin(), row_sum.end(), static_cast<double>(w));
        total = static_cast<double>(n);
    }
    for (int y = 0; y < h; ++y) {
        double running = 0.0;
        for (int x = 0; x < w; ++x) {
            const size_t i = static_cast<size_t>(y) * static_cast<size_t>(w) + static_cast<size_t>(x);
            out[i] = static_cast<float>(f[i] / total);
            running += f[i];
            out[n + i] = row_sum[static_cast<size_t>(y)] > 0.0 ? static_cast<float>(running / row_sum[static_cast<size_t>(y)])
                                                                : static_cast<float>(x + 1) / static_cast<float>(w);
        }
        out[n + static_cast<size_t>(y) * static_cast<size_t>(w) + static_cast<size_t>(w - 1)] = 1.0f;
    }
    double running = 0.0;
    for (int y = 0; y < h; ++y) {
        running += row_sum[static_cast<size_t>(y)];
        out[2 * n + static_cast<size_t>(y)] = static_cast<float>(running / total);
    }
    out[2 * n + static_cast<size_t>(h - 1)] = 1.0f;
    return out;
}

}  // namespace candela::rt
