// The viewer's effect rows: the checkbox is the user's switch, the status beside it is
// what the planner made of it, and the two never contradict each other. Checked over every
// decision the planner can produce, plus the real planner on a sample scene.
#include <gtest/gtest.h>

#include "../../samples/viewer/effect_status.hpp"
#include "effects/gi/gi.hpp"
#include "render/features.hpp"
#include "render/settings.hpp"
#include "scene/gltf_loader.hpp"

namespace candela::viewer {
namespace {

bool starts_with(const std::string& s, const std::string& prefix) { return s.rfind(prefix, 0) == 0; }

TEST(ViewerEffectStatus, TickedBoxNeverSaysOffAndUntickedNeverSaysRunningUnlessForced) {
    for (int bits = 0; bits < 32; ++bits) {
        const bool switch_on = bits & 1;
        EffectDecision d;
        d.name = "transparency";
        d.enabled = bits & 2;
        d.needed = bits & 4;
        d.implemented = bits & 8;
        d.planned = (bits & 16) && d.enabled && d.implemented;  // gating off may plan an unneeded effect
        d.reason = d.planned ? "on: 2 BLEND materials" : d.needed ? "off: switched off (--effects); the scene has 2 BLEND materials"
                                                                 : "off: no BLEND materials";
        const EffectStatus s = effect_status(switch_on, d);
        SCOPED_TRACE("bits " + std::to_string(bits) + ": " + s.label + " / " + s.detail);
        EXPECT_FALSE(starts_with(s.label, "off")) << "the label says what happened, not the planner's prefix";
        EXPECT_FALSE(starts_with(s.detail, "off:") || starts_with(s.detail, "on:")) << "the prefix is stripped";
        EXPECT_FALSE(s.detail.empty());
        if (d.planned) {
            EXPECT_EQ(s.state, EffectState::running);
            EXPECT_TRUE(starts_with(s.label, "running"));
            // Running with the box unticked happens only when a debug view forces it: say so.
            if (!switch_on) EXPECT_NE(s.label.find("debug view"), std::string::npos);
        } else if (switch_on) {
            EXPECT_EQ(s.state, EffectState::skipped);
            EXPECT_TRUE(starts_with(s.label, "skipped: ")) << "a ticked box that does not run says why";
            EXPECT_EQ(s.label.find("switched off"), std::string::npos);
        } else {
            EXPECT_EQ(s.state, EffectState::switched_off);
            EXPECT_EQ(s.label, "switched off");
            EXPECT_EQ(s.detail.find("switched off"), std::string::npos) << "said once, in the label";
        }
    }
}

TEST(ViewerEffectStatus, PlannerReasonsOnTheCornellBox) {
    const Scene scene = load_gltf(std::string(CANDELA_SOURCE_DIR) + "/samples/scenes/cornell_box.gltf");
    RenderSettings settings;  // every effect switched on
    const Features on = analyze(scene, settings);
    // The Cornell box has no BLEND material: the ticked transparency box is skipped, with the reason.
    const EffectStatus transparency = effect_status(settings.on("transparency"), on.decision("transparency"));
    EXPECT_EQ(transparency.label, "skipped: not needed");
    EXPECT_EQ(transparency.detail, "no BLEND materials");
    const EffectStatus shadows = effect_status(settings.on("shadows"), on.decision("shadows"));
    EXPECT_EQ(shadows.label, "running");
    EXPECT_FALSE(shadows.detail.empty());

    settings.set_on("shadows", false);
    const Features off = analyze(scene, settings);
    const EffectStatus switched = effect_status(settings.on("shadows"), off.decision("shadows"));
    EXPECT_EQ(switched.label, "switched off");
    EXPECT_NE(switched.detail.find("it would run"), std::string::npos) << switched.detail;
    EXPECT_EQ(switched.detail.find("--effects"), std::string::npos) << switched.detail;
}

// GI in the viewer: it spreads the GI probe updates over frames unless the user's --set says
// otherwise (0 there: converge before each frame, as a still does).
TEST(ViewerGi, BudgetDefaultsToTheViewersUnlessSetOnTheCommandLine) {
    RenderSettings s;
    ASSERT_EQ(s.get<GiOptions>().budget, 0) << "a still converges before its frame";
    apply_viewer_defaults(s, {"gi.bias=0.2", "ssao.samples=8"});
    EXPECT_EQ(s.get<GiOptions>().budget, kGiInteractiveBudget) << "other knobs leave the viewer's default";
    for (const char* given : {"gi.budget=0", "gi.budget=4096"}) {
        RenderSettings user;
        apply_knob(user, given);
        const int value = user.get<GiOptions>().budget;
        apply_viewer_defaults(user, {"ssao.samples=8", given});
        EXPECT_EQ(user.get<GiOptions>().budget, value) << given;
    }
    EXPECT_FALSE(sets_knob({"gi.budgets=1", "gi.budge=1", "xgi.budget=1"}, "gi.budget"));
    // 16384 rays are whole 64-probe batches of 128-ray probes: the same batches as a still.
    EXPECT_EQ(kGiInteractiveBudget % (64 * GiOptions{}.rays), 0);
}

TEST(ViewerGi, PanelLineSaysConvergingThenConverged) {
    GiStatus st;
    EXPECT_EQ(gi_status_line(st, kGiInteractiveBudget), "") << "not planned: the effect row says why";
    st.planned = true;
    st.counts = {8, 4, 2};
    st.rays = 128;
    st.bounces = 5;
    st.updates_planned = 11;
    st.updates_done = 3;
    st.rays_last_frame = 16384;
    // 8 updates of 64 probes x 128 rays left, 16384 rays per frame: at most 4 frames.
    EXPECT_EQ(gi_status_line(st, 16384),
              "GI probes 8x4x2, 128 rays, 5 bounce(s): 3/11 updates done (converging, 16384 rays/frame, <= 4 frames to go)");
    // A budget below one probe still traces one probe per frame.
    EXPECT_NE(gi_status_line(st, 1).find("<= 512 frames to go"), std::string::npos) << gi_status_line(st, 1);
    st.updates_done = 11;
    st.rays_last_frame = 0;
    EXPECT_EQ(gi_status_line(st, 16384), "GI probes 8x4x2, 128 rays, 5 bounce(s): converged (11 updates)");
    EXPECT_EQ(gi_status_line(st, 0), "GI probes 8x4x2, 128 rays, 5 bounce(s): converged (11 updates, before the frame: gi.budget=0)");
    st.nonfinite = 2;
    EXPECT_NE(gi_status_line(st, 0).find("2 non-finite"), std::string::npos);
}

}  // namespace
}  // namespace candela::viewer
