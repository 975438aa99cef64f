#pragma once
// What the raster-against-reference tests share: a raster frame with settings (a debug buffer or
// radiance) and a ray-traced render of the same scene and camera, both checked for NaN/Inf.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "gl_fixture.hpp"
#include "render/renderer.hpp"
#include "effects/shadows/shadows.hpp"
#include "rt/ray_tracer.hpp"

namespace candela::test {

class ReferenceTest : public GlContextTest {
protected:
    // The scene's first camera (else the framing camera) at w x h; returns linear radiance.
    ImageF raster(const Scene& scene, int w, int h, const RenderSettings& settings) {
        GpuScene gpu(scene);
        Renderer renderer(lib_, scene, gpu, settings);
        renderer.render(scene.select_camera("", static_cast<float>(w) / static_cast<float>(h)), w, h);
        last_views_ = renderer.effect_runtime<ShadowsRuntime>()->views();
        ImageF img = renderer.read_radiance();
        EXPECT_EQ(count_nonfinite(img), 0u);
        return img;
    }
    // Default settings with these effects and knobs applied.
    static RenderSettings settings(const std::string& effects, const std::vector<std::string>& knobs) {
        RenderSettings s;
        if (!effects.empty()) apply_effects(s, effects);
        for (const auto& k : knobs) apply_knob(s, k);
        return s;
    }
    rt::Result traced(const Scene& scene, int w, int h, const rt::Options& options) {
        GpuScene gpu(scene);
        rt::RayTracer tracer(lib_, scene, gpu, options);
        rt::Result r = tracer.render(scene.select_camera("", static_cast<float>(w) / static_cast<float>(h)), w, h);
        EXPECT_EQ(r.nonfinite_samples, 0u);
        EXPECT_EQ(count_nonfinite(r.image), 0u);
        return r;
    }
    // `path` at pixel centres (as the rasterizer samples), w x h, in 4 independent batches of
    // spp / 4 samples: the mean luminance of the image, and in `standard_error` that of the mean
    // from the batches' spread.
    double path_mean_luminance(const Scene& scene, int w, int h, int spp, double& standard_error) {
        rt::Options o;
        o.mode = rt::Mode::path;
        o.spp = spp;
        o.jitter = 0;
        GpuScene gpu(scene);
        rt::RayTracer tracer(lib_, scene, gpu, o);
        const Camera camera = scene.select_camera("", static_cast<float>(w) / static_cast<float>(h));
        double means[4], mean = 0.0;
        for (int k = 0; k < 4; ++k) {
            tracer.set_shard(k, 4);
            const rt::Result r = tracer.render(camera, w, h);
            EXPECT_EQ(r.nonfinite_samples, 0u);
            EXPECT_EQ(count_nonfinite(r.image), 0u);
            means[k] = mean_luminance(r.image);
            mean += means[k] / 4.0;
        }
        double var = 0.0;
        for (double b : means) var += (b - mean) * (b - mean) / 3.0;
        standard_error = std::sqrt(var / 4.0);
        return mean;
    }
    ShaderLibrary lib_{std::filesystem::path(CANDELA_SOURCE_DIR) / "shaders"};
    ShadowViews last_views_;  // of the last raster() frame
};

}  // namespace candela::test
