#include "accuracy/metrics.hpp"

#include <algorithm>
#include <cmath>

namespace candela::accuracy {

namespace {

// AccuracySweep::Region::edges: the pixels whose 3x3 neighbourhood in the reference spans more than
// a tenth of its largest luminance.
std::vector<bool> edge_mask(const ImageF& ref) {
    const int w = ref.width, h = ref.height;
    auto lum = [&](int x, int y) {
        const float* p = ref.at(std::clamp(x, 0, w - 1), std::clamp(y, 0, h - 1));
        return 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
    };
    double top = 0.0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) top = std::max(top, lum(x, y));
    std::vector<bool> mask(static_cast<size_t>(w) * static_cast<size_t>(h), false);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            double lo = 1e30, hi = -1e30;
            for (int j = -1; j <= 1; ++j)
                for (int i = -1; i <= 1; ++i) lo = std::min(lo, lum(x + i, y + j)), hi = std::max(hi, lum(x + i, y + j));
            mask[static_cast<size_t>(y) * static_cast<size_t>(w) + static_cast<size_t>(x)] = hi - lo > 0.1 * top;
        }
    return mask;
}

}  // namespace

// The errors over the edge pixels only (RMSE over RGB, relative MSE, max, share over 2/255 after
// tone mapping) and the reference's noise there.
void measure_edge_errors(Row& row, const ImageF& img, const Reference& ref) {
    const std::vector<bool> mask = edge_mask(ref.image);
    const ImageF a = to_display(img, 0.0f), b = to_display(ref.image, 0.0f);
    double se = 0, rel = 0, noise = 0, mx = 0;
    size_t n = 0, over = 0;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
            if (!mask[static_cast<size_t>(y) * static_cast<size_t>(img.width) + static_cast<size_t>(x)]) continue;
            ++n;
            bool failing = false;
            for (int c = 0; c < 3; ++c) {
                const double d = img.at(x, y)[c] - ref.image.at(x, y)[c];
                se += d * d;
                rel += d * d / (ref.image.at(x, y)[c] * ref.image.at(x, y)[c] + 1e-2);
                noise += static_cast<double>(ref.half_diff.at(x, y)[c]) * ref.half_diff.at(x, y)[c];
                mx = std::max(mx, std::abs(d));
                failing = failing || std::abs(a.at(x, y)[c] - b.at(x, y)[c]) > 2.0 / 255.0;
            }
            over += failing ? 1 : 0;
        }
    const double k = std::max<double>(1.0, 3.0 * static_cast<double>(n));
    row.rmse = std::sqrt(se / k);
    row.relmse = rel / k;
    row.max_abs = mx;
    row.pct_over = 100.0 * static_cast<double>(over) / std::max<double>(1.0, static_cast<double>(n));
    row.ref_spp = ref.spp;
    row.ref_noise = std::sqrt(noise / k);
    row.at_noise_floor = row.ref_noise > 0.0 && row.rmse <= 1.5 * row.ref_noise;
}

void measure_errors(Row& row, const ImageF& img, const Reference& ref, Buffer buffer) {
    const CompareResult m = compare(img, ref.image, 2.0 / 255.0);
    row.rmse = m.rmse;
    row.relmse = m.relative_mse;
    row.max_abs = m.max_abs;
    // Radiance is judged after tone mapping; AO and visibility are already in [0, 1].
    const bool display = buffer == Buffer::radiance || buffer == Buffer::indirect;
    row.pct_over = 100.0 * (display ? compare(to_display(img, 0.0f), to_display(ref.image, 0.0f), 2.0 / 255.0) : m).failing_fraction;
    row.ref_spp = ref.spp;
    row.ref_noise = ref.noise;
    row.at_noise_floor = ref.noise > 0.0 && row.rmse <= 1.5 * ref.noise;
}

void mark_pareto(std::vector<Row>& rows, size_t first) {
    for (size_t i = first; i < rows.size(); ++i) {
        Row& r = rows[i];
        if (!std::isfinite(r.ms) || !std::isfinite(r.rmse)) continue;
        r.pareto = true;
        for (size_t j = first; j < rows.size(); ++j) {
            const Row& o = rows[j];
            if (j == i || !std::isfinite(o.ms) || !std::isfinite(o.rmse)) continue;
            if (o.ms <= r.ms && o.rmse <= r.rmse && (o.ms < r.ms || o.rmse < r.rmse)) {
                r.pareto = false;
                break;
            }
        }
    }
}

// The Pareto row nearest the utopia point (least time and least error) in log-log.
int knee(const std::vector<Row>& rows, size_t first, size_t last) {
    double min_ms = 1e30, min_e = 1e30;
    for (size_t i = first; i < last; ++i)
        if (rows[i].pareto) min_ms = std::min(min_ms, std::max(rows[i].ms, 1e-3)), min_e = std::min(min_e, std::max(rows[i].rmse, 1e-6));
    int best = -1;
    double best_d = 1e30;
    for (size_t i = first; i < last; ++i) {
        if (!rows[i].pareto) continue;
        const double dx = std::log10(std::max(rows[i].ms, 1e-3) / min_ms), dy = std::log10(std::max(rows[i].rmse, 1e-6) / min_e);
        if (dx * dx + dy * dy < best_d) best_d = dx * dx + dy * dy, best = static_cast<int>(i);
    }
    return best;
}

}  // namespace candela::accuracy
