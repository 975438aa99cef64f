#include "effects/gi/estimate.hpp"

#include <algorithm>
#include <vector>
#include <chrono>
#include <cstdio>

#include "rt/ray_tracer.hpp"

namespace candela {

std::string IndirectEstimate::text() const {
    char buf[160];
    std::snprintf(buf, sizeof buf, "%.0f %% of the light on the image's surfaces (one diffuse bounce / direct light as a geometric series; %dx%d px x %d spp, %.0f ms)", fraction * 100.0,
                  width, height, spp, ms);
    return buf;
}

IndirectEstimate estimate_indirect(const ShaderLibrary& shaders, const Scene& scene, GpuScene& gpu) {
    const auto t0 = std::chrono::steady_clock::now();
    IndirectEstimate e;
    // 48x32 pixels, 8 samples: 12288 paths per render, so each mean's standard error is a few
    // tenths of a percent of the image; the cost is the BVH and two programs.
    e.width = 48;
    e.height = 32;
    e.spp = 8;
    const Camera camera = scene.select_camera("", static_cast<float>(e.width) / static_cast<float>(e.height));
    // One tracer for both renders: the BVH is built and uploaded once (set_mode keeps it and
    // gives the images a fresh tracer of the mode would, same seed and program).
    rt::Options o;
    o.mode = rt::Mode::direct;
    o.spp = e.spp;
    o.tile_rows = e.height;
    rt::RayTracer tracer(shaders, scene, gpu, o);
    auto render = [&] {
        const ImageF img = tracer.render(camera, e.width, e.height).image;
        std::vector<double> lum(static_cast<size_t>(img.width) * static_cast<size_t>(img.height));
        for (size_t i = 0; i < lum.size(); ++i) {
            const float* p = img.pixels.data() + i * static_cast<size_t>(img.channels);
            lum[i] = 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
        }
        return lum;
    };
    // What the probes would add is diffuse interreflection: the tracer's `indirect` mode (one
    // diffuse bounce) against `direct` (emission, sky and direct light, every BRDF lobe).
    // Specular paths (mirrors, glass) are the reflection effect's, not counted here.
    const std::vector<double> direct = render();
    tracer.set_mode(rt::Mode::indirect);
    const std::vector<double> bounce = render();
    // Emitters seen by the camera are far brighter than what they light: pixels above 10x the
    // median of `direct` are left out, so that a ceiling light does not hide the room's share.
    std::vector<double> sorted = direct;
    std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2), sorted.end());
    const double cutoff = 10.0 * sorted[sorted.size() / 2];
    double d = 0.0, i1 = 0.0;
    for (size_t k = 0; k < direct.size(); ++k)
        if (direct[k] <= cutoff) d += direct[k], i1 += bounce[k];
    e.direct_mean = d / static_cast<double>(direct.size());
    e.one_bounce_mean = i1 / static_cast<double>(direct.size());
    // Every bounce returns about rho = I1/D of the light the one before it had, so the indirect
    // light is D (rho + rho^2 + ...) and its share of the image D/(1-rho) is rho.
    e.fraction = d > 0.0 ? std::clamp(i1 / d, 0.0, 0.99) : 0.0;
    e.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return e;
}

}  // namespace candela
