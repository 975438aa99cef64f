#include "rt/view_light.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <vector>

#include "rt/ray_tracer.hpp"

namespace candela {

std::string ViewLight::text() const {
    char buf[320];
    std::snprintf(buf, sizeof buf,
                  "%dx%d px x %d spp: %.0f %% passive surface, %.0f %% emitter, %.0f %% background; %d surface px, %d lit, "
                  "%.0f %% unlit; one bounce / direct %.3f +- %.3f; %.0f ms",
                  width, height, spp, passive_share * 100.0, emitter_share * 100.0, background_share * 100.0, surface_pixels,
                  lit_pixels, unlit_share * 100.0, ratio, ratio_stderr, ms);
    return buf;
}

ViewLight measure_view_light(const ShaderLibrary& shaders, const Scene& scene, GpuScene& gpu, const Camera& camera, float aspect,
                             int spp) {
    const auto t0 = std::chrono::steady_clock::now();
    ViewLight v;
    const double a = std::isfinite(aspect) && aspect > 0.0f ? std::clamp(static_cast<double>(aspect), 1.0 / 16.0, 16.0) : 1.0;
    v.width = std::max(4, static_cast<int>(std::lround(std::sqrt(kViewLightPixels * a))));
    v.height = std::max(4, static_cast<int>(std::lround(kViewLightPixels / static_cast<double>(v.width))));
    v.spp = spp;
    rt::Options o;
    o.mode = rt::Mode::direct;
    o.spp = spp;
    o.tile_rows = v.height;
    o.camera_sees_emission = false;
    // One tracer for the three renders: the BVH is built and uploaded once.
    rt::RayTracer tracer(shaders, scene, gpu, o);
    const size_t n = static_cast<size_t>(v.width) * static_cast<size_t>(v.height);
    // channel < 0: luminance; else that channel.
    auto channel = [&](const ImageF& img, int c) {
        std::vector<double> out(n);
        for (size_t i = 0; i < n; ++i) {
            const float* p = img.pixels.data() + i * static_cast<size_t>(img.channels);
            out[i] = c < 0 ? 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2] : p[c];
            if (!std::isfinite(out[i])) out[i] = 0.0;
        }
        return out;
    };
    const std::vector<double> direct = channel(tracer.render(camera, v.width, v.height).image, -1);
    tracer.set_mode(rt::Mode::indirect);
    const std::vector<double> bounce = channel(tracer.render(camera, v.width, v.height).image, -1);
    tracer.set_mode(rt::Mode::hits);
    const ImageF hits = tracer.render(camera, v.width, v.height).image;
    const std::vector<double> passive = channel(hits, 0), emitter = channel(hits, 1);
    double d = 0.0, i1 = 0.0, wsum = 0.0, esum = 0.0;
    std::vector<double> surface_light, lit_direct;
    for (size_t k = 0; k < n; ++k) {
        const double w = std::clamp(passive[k], 0.0, 1.0);
        wsum += w;
        esum += std::clamp(emitter[k], 0.0, 1.0);
        d += direct[k];  // the direct render is already 0 where the camera sees no surface
        i1 += bounce[k] * w;
        if (w >= 0.5) {
            surface_light.push_back(direct[k] + bounce[k]);
            if (direct[k] > 0.0) lit_direct.push_back(direct[k]);
        }
    }
    const double nd = static_cast<double>(n);
    v.passive_share = wsum / nd;
    v.emitter_share = esum / nd;
    v.background_share = std::max(0.0, 1.0 - v.passive_share - v.emitter_share);
    v.direct_mean = d / nd;
    v.bounce_mean = i1 / nd;
    v.surface_pixels = static_cast<int>(surface_light.size());
    v.lit_pixels = static_cast<int>(lit_direct.size());
    if (d > 0.0) {
        v.ratio = i1 / d;
        double r2 = 0.0;
        for (size_t k = 0; k < n; ++k) {
            const double r = bounce[k] * std::clamp(passive[k], 0.0, 1.0) - v.ratio * direct[k];
            r2 += r * r;
        }
        v.ratio_stderr = std::sqrt(nd / std::max(nd - 1.0, 1.0) * r2) / d;
    }
    if (!surface_light.empty()) {
        double level = 0.0;
        if (!lit_direct.empty()) {
            std::nth_element(lit_direct.begin(), lit_direct.begin() + static_cast<std::ptrdiff_t>(lit_direct.size() / 2), lit_direct.end());
            level = lit_direct[lit_direct.size() / 2];
        }
        size_t unlit = 0;
        for (double l : surface_light) unlit += !(l > kUnlitLevel * level) || level <= 0.0;
        v.unlit_share = static_cast<double>(unlit) / static_cast<double>(surface_light.size());
    }
    v.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return v;
}

}  // namespace candela
