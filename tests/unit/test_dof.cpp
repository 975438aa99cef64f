// The raster depth of field (engine/effects/dof/) judged against the tracer's thin lens: planned
// only when the camera has an aperture (its own or --set camera.aperture), no change at all with
// a pinhole, closer to the traced depth of field on generated:dof than the sharp raster image is
// and within a stated error, and never NaN or Inf, even with absurd lenses.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "reference_fixture.hpp"
#include "render/features.hpp"
#include "scene/generate.hpp"

namespace candela {
namespace {

bool planned(const Scene& scene, const RenderSettings& s) {
    const Camera camera = scene.select_camera("", 4.0f / 3.0f);
    const Features f = analyze(scene, s, nullptr, &camera);
    bool gather = false;
    for (const PlannedPass& p : plan_passes(f, s)) gather = gather || p.name == "dof_gather";
    EXPECT_EQ(gather, f.decision("dof").planned);
    return f.decision("dof").planned;
}

RenderSettings with(const std::vector<std::string>& knobs) {
    RenderSettings s;
    for (const auto& k : knobs) apply_knob(s, k);
    return s;
}

TEST(Dof, PlannedOnlyWithAnAperture) {
    const Scene dof = make_dof_scene();
    ASSERT_GT(dof.cameras.at(0).aperture, 0.0f);
    EXPECT_TRUE(planned(dof, with({})));  // the camera's own lens
    EXPECT_FALSE(planned(dof, with({"camera.aperture=0"})));
    EXPECT_FALSE(planned(dof, with({"camera.aperture=0.2", "debug.view=ao"})));  // debug buffers stay sharp
    RenderSettings off;
    apply_effects(off, "shadows");
    EXPECT_FALSE(planned(dof, off));  // switched off
    {
        const Camera camera = dof.select_camera("", 1.0f);
        const Features f = analyze(dof, with({"camera.aperture=0"}), nullptr, &camera);
        EXPECT_EQ(f.decision("dof").reason, "off: pinhole camera (aperture 0)");
    }
    const Scene pinhole = make_many_lights_scene(2);
    ASSERT_EQ(pinhole.cameras.at(0).aperture, 0.0f);
    EXPECT_FALSE(planned(pinhole, with({})));
    EXPECT_TRUE(planned(pinhole, with({"camera.aperture=0.05"})));
    // Without a camera, analyze() plans from the settings' lens alone.
    EXPECT_TRUE(analyze(pinhole, with({"camera.aperture=0.05"})).decision("dof").planned);
    EXPECT_FALSE(analyze(pinhole, with({})).decision("dof").planned);
}

class DofTest : public test::ReferenceTest {};


TEST_P(DofTest, PinholeIsBitIdenticalToNoModule) {
    const Scene scene = make_dof_scene();
    const ImageF without = raster(scene, 96, 72, settings("shadows", {"camera.aperture=0"}));
    const ImageF pinhole = raster(scene, 96, 72, settings("shadows,dof", {"camera.aperture=0"}));
    EXPECT_EQ(pinhole.pixels, without.pixels);
    // Forced on with a pinhole (render.gating=off), the passes run and change nothing either.
    const ImageF forced = raster(scene, 96, 72, settings("shadows,dof", {"camera.aperture=0", "render.gating=off"}));
    EXPECT_EQ(forced.pixels, without.pixels);
    // With the camera's aperture the image does change.
    EXPECT_NE(raster(scene, 96, 72, settings("shadows,dof", {})).pixels, without.pixels);
}

// generated:dof at 160 x 120 against `direct` with the lens sampled and the pixel box-filtered.
// Measured (2026-12-03, llvmpipe): RMSE 0.0366 with DOF, 0.0786 for the pinhole raster against the
// same reference; the reference's own noise is 0.013 at 64 spp, and the raster pinhole image is
// 0.052 from the traced pinhole image (its aliased edges, which the blur mostly hides). Bound:
// 0.045, and under 0.6 x the pinhole's error.
TEST_P(DofTest, CloserToTheTracedLensThanThePinhole) {
    const Scene scene = make_dof_scene();
    const int w = 160, h = 120;
    rt::Options o;
    o.mode = rt::Mode::direct;
    o.spp = 64;
    o.jitter = 1;
    const ImageF reference = traced(scene, w, h, o).image;
    const ImageF dof = raster(scene, w, h, settings("shadows,dof", {}));
    const ImageF pinhole = raster(scene, w, h, settings("shadows,dof", {"camera.aperture=0"}));
    const double e_dof = rmse(dof, reference), e_pinhole = rmse(pinhole, reference);
    RecordProperty("rmse_dof", std::to_string(e_dof));
    RecordProperty("rmse_pinhole", std::to_string(e_pinhole));
    EXPECT_LT(e_dof, 0.6 * e_pinhole) << "dof " << e_dof << " pinhole " << e_pinhole;
    EXPECT_LT(e_dof, 0.045) << "dof " << e_dof << " pinhole " << e_pinhole;
}

TEST_P(DofTest, NoNaNOrInfWithExtremeLenses) {
    const Scene scene = make_dof_scene();
    for (const std::vector<std::string>& knobs :
         std::vector<std::vector<std::string>>{{"camera.aperture=1000", "camera.focus_distance=0.0001"},
                                               {"camera.aperture=0.5", "camera.focus_distance=0"},  // auto focus
                                               {"camera.aperture=1e-6"},
                                               {"camera.aperture=5", "camera.focus_distance=1e9", "dof.max_coc=256", "dof.samples=4"}}) {
        const ImageF img = raster(scene, 64, 48, settings("shadows,dof", knobs));  // raster() counts non-finite pixels
        EXPECT_EQ(count_nonfinite(img), 0u);
        float peak = 0.0f;
        for (float v : img.pixels) peak = std::max(peak, v);
        EXPECT_GT(peak, 0.0f);  // not black either
    }
}

INSTANTIATE_TEST_SUITE_P(Backends, DofTest, ::testing::Values(Backend::egl), test::backend_name);

}  // namespace
}  // namespace candela
