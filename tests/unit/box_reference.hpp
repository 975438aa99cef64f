#pragma once
// The tracer's box-filtered pixels as a statistical reference (anti-aliasing tests):
// `batches` independent `direct` traces (seeds first_seed, first_seed + 1, ...) of `spp` jittered
// camera rays per pixel, and per pixel the mean of channel 0 and its standard error from the
// spread of the batch means.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "image/image.hpp"
#include "render/gpu_scene.hpp"
#include "rt/ray_tracer.hpp"
#include "scene/scene.hpp"
#include "shader/shader_library.hpp"

namespace candela::test {

struct BoxReference {
    std::vector<double> mean, se;  // per pixel (row-major, top row first), channel 0
};

inline BoxReference trace_box_reference(const ShaderLibrary& lib, const Scene& scene, int w, int h, int batches, int spp,
                                        std::uint32_t first_seed) {
    std::vector<ImageF> runs;
    for (int k = 0; k < batches; ++k) {
        rt::Options o;
        o.mode = rt::Mode::direct;
        o.spp = spp;
        o.seed = first_seed + static_cast<std::uint32_t>(k);
        o.jitter = 1;
        GpuScene gpu(scene);
        rt::Result r = rt::RayTracer(lib, scene, gpu, o).render(scene.select_camera("", 1.0f), w, h);
        EXPECT_EQ(count_nonfinite(r.image), 0u);
        runs.push_back(std::move(r.image));
    }
    BoxReference ref;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            double s = 0, s2 = 0;
            for (const ImageF& im : runs) {
                s += im.at(x, y)[0];
                s2 += static_cast<double>(im.at(x, y)[0]) * im.at(x, y)[0];
            }
            const double m = s / batches, var = std::max(0.0, (s2 - s * m) / (batches - 1));
            ref.mean.push_back(m);
            ref.se.push_back(std::sqrt(var / batches));
        }
    return ref;
}

}  // namespace candela::test
