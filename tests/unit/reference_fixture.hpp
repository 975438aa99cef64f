#pragma once
// What the raster-against-reference tests share: a raster frame with settings (a debug buffer or
// radiance) and a ray-traced render of the same scene and camera, both checked for NaN/Inf.
#include <gtest/gtest.h>

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
    ShaderLibrary lib_{std::filesystem::path(CANDELA_SOURCE_DIR) / "shaders"};
    ShadowViews last_views_;  // of the last raster() frame
};

}  // namespace candela::test
