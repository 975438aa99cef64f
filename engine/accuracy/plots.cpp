#include "accuracy/plots.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>

namespace candela::accuracy {
namespace fs = std::filesystem;

void write_plot(const fs::path& path, const std::string& title, const std::vector<Row>& rows, double noise, double rt_ms) {
    const double W = 640, H = 400, L = 70, R = 20, T = 30, B = 50;
    double x0 = 1e30, x1 = -1e30, y0 = 1e30, y1 = -1e30;
    auto lx = [](double ms) { return std::log10(std::max(ms, 1e-3)); };
    auto ly = [](double e) { return std::log10(std::max(e, 1e-6)); };
    for (const Row& r : rows) {
        if (!std::isfinite(r.ms) || !std::isfinite(r.rmse)) continue;
        x0 = std::min(x0, lx(r.ms)), x1 = std::max(x1, lx(r.ms));
        y0 = std::min(y0, ly(r.rmse)), y1 = std::max(y1, ly(r.rmse));
    }
    if (x0 > x1) return;
    if (noise > 0) y0 = std::min(y0, ly(noise)), y1 = std::max(y1, ly(noise));
    if (rt_ms > 0) x0 = std::min(x0, lx(rt_ms)), x1 = std::max(x1, lx(rt_ms));
    x0 = std::floor(x0 - 0.05), x1 = std::ceil(x1 + 0.05), y0 = std::floor(y0 - 0.05), y1 = std::ceil(y1 + 0.05);
    auto px = [&](double v) { return L + (v - x0) / (x1 - x0) * (W - L - R); };
    auto py = [&](double v) { return H - B - (v - y0) / (y1 - y0) * (H - T - B); };
    std::ofstream f(path);
    f << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << W << "\" height=\"" << H << "\" font-family=\"sans-serif\" font-size=\"11\">\n";
    f << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
    f << "<text x=\"" << W / 2 << "\" y=\"18\" text-anchor=\"middle\" font-size=\"14\">" << title << "</text>\n";
    for (double d = x0; d <= x1 + 1e-9; d += 1.0) {
        f << "<line x1=\"" << px(d) << "\" y1=\"" << T << "\" x2=\"" << px(d) << "\" y2=\"" << H - B << "\" stroke=\"#ddd\"/>\n";
        f << "<text x=\"" << px(d) << "\" y=\"" << H - B + 15 << "\" text-anchor=\"middle\">" << num(std::pow(10.0, d), "%g") << "</text>\n";
    }
    for (double d = y0; d <= y1 + 1e-9; d += 1.0) {
        f << "<line x1=\"" << L << "\" y1=\"" << py(d) << "\" x2=\"" << W - R << "\" y2=\"" << py(d) << "\" stroke=\"#ddd\"/>\n";
        f << "<text x=\"" << L - 5 << "\" y=\"" << py(d) + 4 << "\" text-anchor=\"end\">" << num(std::pow(10.0, d), "%g") << "</text>\n";
    }
    f << "<text x=\"" << W / 2 << "\" y=\"" << H - 12 << "\" text-anchor=\"middle\">ms of the effect's passes (log)</text>\n";
    f << "<text transform=\"translate(16," << (H - B + T) / 2 << ") rotate(-90)\" text-anchor=\"middle\">RMSE vs reference (log)</text>\n";
    if (noise > 0)
        f << "<line x1=\"" << L << "\" y1=\"" << py(ly(noise)) << "\" x2=\"" << W - R << "\" y2=\"" << py(ly(noise))
          << "\" stroke=\"#36c\" stroke-dasharray=\"6,4\"/><text x=\"" << W - R - 4 << "\" y=\"" << py(ly(noise)) - 4
          << "\" text-anchor=\"end\" fill=\"#36c\">reference noise</text>\n";
    if (rt_ms > 0)
        f << "<line x1=\"" << px(lx(rt_ms)) << "\" y1=\"" << T << "\" x2=\"" << px(lx(rt_ms)) << "\" y2=\"" << H - B
          << "\" stroke=\"#c63\" stroke-dasharray=\"6,4\"/><text x=\"" << px(lx(rt_ms)) - 4 << "\" y=\"" << T + 12
          << "\" text-anchor=\"end\" fill=\"#c63\">ray tracer</text>\n";
    std::vector<const Row*> front;
    for (const Row& r : rows)
        if (r.pareto) front.push_back(&r);
    std::sort(front.begin(), front.end(), [](const Row* a, const Row* b) { return a->ms < b->ms; });
    if (front.size() > 1) {
        f << "<polyline fill=\"none\" stroke=\"#d22\" stroke-width=\"1.5\" points=\"";
        for (const Row* r : front) f << px(lx(r->ms)) << "," << py(ly(r->rmse)) << " ";
        f << "\"/>\n";
    }
    for (const Row& r : rows) {
        if (!std::isfinite(r.ms) || !std::isfinite(r.rmse)) continue;
        f << "<circle cx=\"" << px(lx(r.ms)) << "\" cy=\"" << py(ly(r.rmse)) << "\" r=\"4\" fill=\"" << (r.pareto ? "#d22" : "#999")
          << "\"/><text x=\"" << px(lx(r.ms)) + 6 << "\" y=\"" << py(ly(r.rmse)) - 5 << "\" font-size=\"9\" fill=\"#555\">" << r.variant
          << "</text>\n";
    }
    f << "</svg>\n";
}

// raster | reference | difference (red at 0.1), display values.
void write_strip(const fs::path& path, const ImageF& raster, const ImageF& reference, Buffer buffer) {
    const bool tonemap = buffer == Buffer::radiance || buffer == Buffer::indirect;
    const ImageF a = tonemap ? to_display(raster, 0.0f) : raster;
    const ImageF b = tonemap ? to_display(reference, 0.0f) : reference;
    const ImageF d = heatmap(raster, reference, 0.1);
    const int w = a.width, h = a.height, gap = 4;
    ImageF strip(3 * w + 2 * gap, h, 4);
    for (int y = 0; y < h; ++y)
        for (int k = 0; k < 3; ++k) {
            const ImageF& src = k == 0 ? a : k == 1 ? b : d;
            for (int x = 0; x < w; ++x) {
                float* o = strip.at(k * (w + gap) + x, y);
                const float* p = src.at(x, y);
                for (int ch = 0; ch < 3; ++ch) o[ch] = std::clamp(p[ch], 0.0f, 1.0f);
                o[3] = 1.0f;
            }
        }
    write_display_image(path, strip);
}

}  // namespace candela::accuracy
