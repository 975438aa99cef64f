// The viewer's adaptive quality (samples/viewer/adaptive_quality.hpp): moving frames that are
// slow step down the ladder (reduced effects, then smaller sizes), a still view gets full
// quality back, frame times near the target settle instead of alternating, and the reduced
// settings really lower the knobs they name.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <random>

#include <nlohmann/json.hpp>

#include "../../samples/viewer/adaptive_quality.hpp"
#include "../../samples/viewer/effect_status.hpp"

namespace candela::viewer {
namespace {

// Drives the controller like the viewer's frame loop: `frames` frames of `dt` seconds, the view
// moving in each, a frame's time given by `cost` of the scale it renders at. Returns the clock.
double drive(AdaptiveQuality& q, double now, int frames, double dt, const std::function<double(float)>& cost, bool moving = true) {
    for (int i = 0; i < frames; ++i) {
        now += dt;
        const QualityState s = q.update(moving, now);
        if (s.level != QualityLevel::full) q.measured(cost(s.scale));
    }
    return now;
}

// A frame whose cost is in proportion to its pixels.
double pixels(float scale, double full_ms) { return full_ms * static_cast<double>(scale) * static_cast<double>(scale); }

TEST(ViewerAdaptiveQuality, StillViewIsFullQuality) {
    AdaptiveQuality q;
    for (int i = 0; i < 5; ++i) {
        const QualityState s = q.update(false, 0.1 * i);
        EXPECT_EQ(s.level, QualityLevel::full);
        EXPECT_EQ(s.scale, 1.0f);
        q.measured(900.0);  // a slow still frame steers nothing
    }
    EXPECT_EQ(q.step_changes(), 0);
}

TEST(ViewerAdaptiveQuality, MovingReducesEffectsFirst) {
    AdaptiveQuality q;
    const QualityState s = q.update(true, 1.0);
    EXPECT_EQ(s.level, QualityLevel::reduced);
    EXPECT_EQ(s.scale, 1.0f);
    // Fast enough at the reduced level: it stays there, at full size.
    drive(q, 1.0, 30, 0.05, [](float sc) { return pixels(sc, 60.0); });
    EXPECT_EQ(q.state().level, QualityLevel::reduced);
    EXPECT_EQ(q.state().scale, 1.0f);
}

TEST(ViewerAdaptiveQuality, DegradesWhenMovingAndSlow) {
    AdaptiveQuality q;  // target 100 ms
    const auto cost = [](float sc) { return pixels(sc, 400.0); };
    q.update(true, 0.0);
    q.measured(cost(1.0f));  // 400 ms at the reduced level: a quarter of the pixels meets 100 ms
    const QualityState s = q.update(true, 0.4);
    EXPECT_EQ(s.level, QualityLevel::scaled);
    EXPECT_LE(s.scale, 0.5f);
    EXPECT_GT(s.scale, 0.0f);
    drive(q, 0.4, 20, 0.1, cost);
    EXPECT_EQ(q.state().level, QualityLevel::scaled);
    EXPECT_LE(cost(q.state().scale), q.target_ms()) << "scale " << q.state().scale;
    // Too slow even at the smallest scale: it stays at the bottom of the ladder.
    AdaptiveQuality slow;
    drive(slow, 0.0, 10, 0.1, [](float sc) { return pixels(sc, 5000.0); });
    EXPECT_EQ(slow.state().scale, slow.params().scales.back());
}

TEST(ViewerAdaptiveQuality, RestoresFullQualityWhenStill) {
    AdaptiveQuality q;
    double now = drive(q, 0.0, 10, 0.1, [](float sc) { return pixels(sc, 400.0); });
    ASSERT_EQ(q.state().level, QualityLevel::scaled);
    // Just after the last movement: still reduced (the user may go on moving).
    EXPECT_NE(q.update(false, now + 0.1).level, QualityLevel::full);
    // Still for longer than still_seconds: full quality at full size.
    const QualityState s = q.update(false, now + 0.3);
    EXPECT_EQ(s.level, QualityLevel::full);
    EXPECT_EQ(s.scale, 1.0f);
    EXPECT_FALSE(q.moving());
    // The next movement starts where the last one ended (the scene costs the same).
    EXPECT_EQ(q.update(true, now + 1.0).level, QualityLevel::scaled);
}

TEST(ViewerAdaptiveQuality, DoesNotOscillateNearTheTarget) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> noise(-0.04, 0.04);
    // Frame times around the target at the reduced level (+-4 %), with a fixed cost that does not
    // shrink with the size; then a cost that no scale changes at all.
    const std::vector<std::function<double(float)>> models = {
        [&](float sc) { return (20.0 + pixels(sc, 80.0)) * (1.0 + noise(rng)); },
        [&](float sc) { return (60.0 + pixels(sc, 45.0)) * (1.0 + noise(rng)); },
        [&](float) { return 100.0 * (1.0 + noise(rng)); },
    };
    for (size_t m = 0; m < models.size(); ++m) {
        AdaptiveQuality q;
        double now = drive(q, 0.0, 20, 0.1, models[m]);
        const int settled = q.step_changes();
        const QualityState at = q.state();
        drive(q, now, 300, 0.1, models[m]);
        EXPECT_EQ(q.step_changes(), settled) << "model " << m << ": the level changed after settling";
        EXPECT_EQ(q.state(), at) << "model " << m;
        EXPECT_LE(settled, 4) << "model " << m;
    }
}

TEST(ViewerAdaptiveQuality, StepsBackUpWhenFramesGetCheap) {
    AdaptiveQuality q;
    double now = drive(q, 0.0, 10, 0.1, [](float sc) { return pixels(sc, 900.0); });
    ASSERT_EQ(q.state().scale, q.params().scales.back());
    now = q.update(false, now + 1.0).level == QualityLevel::full ? now + 1.0 : now;
    // A new movement over a view that costs a tenth: up the ladder to the reduced level.
    drive(q, now, 20, 0.1, [](float sc) { return pixels(sc, 60.0); });
    EXPECT_EQ(q.state().level, QualityLevel::reduced);
}

TEST(ViewerAdaptiveQuality, OffRendersFullQualityAndBadInputIsIgnored) {
    AdaptiveQuality q;
    q.set_enabled(false);
    EXPECT_EQ(q.update(true, 0.0).level, QualityLevel::full);
    q.measured(5000.0);
    EXPECT_EQ(q.update(true, 0.1).level, QualityLevel::full);
    q.set_enabled(true);
    EXPECT_EQ(q.update(true, 0.2).level, QualityLevel::reduced);
    q.measured(std::nan(""));
    q.measured(-5.0);
    q.measured(INFINITY);
    EXPECT_EQ(q.update(true, 0.3).level, QualityLevel::reduced);
    q.set_target_ms(std::nan(""));
    EXPECT_EQ(q.target_ms(), 100.0);
    q.set_target_ms(0.0);
    EXPECT_EQ(q.target_ms(), 1.0);
    // A ladder given out of order, with zero, negative and NaN scales, keeps what makes sense.
    AdaptiveParams p;
    p.scales = {0.5f, 0.0f, -1.0f, std::nanf(""), 2.0f, 0.25f, 0.4f};
    p.target_ms = std::nan("");
    const AdaptiveQuality odd(p);
    EXPECT_EQ(odd.params().scales, (std::vector<float>{1.0f, 0.5f, 0.25f}));
    EXPECT_EQ(odd.target_ms(), 100.0);
}

// The viewer's settings: the defaults plus the interactive ones (gi.budget).
RenderSettings viewer_settings(const std::vector<std::string>& set = {}) {
    RenderSettings s;
    apply_viewer_defaults(s, set);
    apply_knobs(s, set);
    return s;
}

TEST(ViewerAdaptiveQuality, ReducedSettingsLowerEveryKnobTheyName) {
    const RenderSettings full = viewer_settings();
    const std::vector<std::string> list = reductions(full);
    const nlohmann::json before = to_json(full)["knobs"];
    const nlohmann::json after = to_json(reduced_settings(full))["knobs"];
    // The costly knobs of the effects the sample scenes run.
    for (const char* knob : {"ssao.samples", "rsm.gather", "rsm.samples", "shadows.pcss_taps", "gi.budget"}) {
        bool named = false;
        for (const std::string& a : list) named |= a.rfind(std::string(knob) + "=", 0) == 0;
        EXPECT_TRUE(named) << knob << " is not lowered by default";
    }
    for (const std::string& a : list) {
        const std::string knob = a.substr(0, a.find('='));
        ASSERT_TRUE(before.contains(knob)) << a;
        // Each assignment took effect and changed its knob (none silently does nothing).
        EXPECT_NE(before[knob], after[knob]) << a;
        if (before[knob].is_number()) EXPECT_LT(after[knob].get<double>(), before[knob].get<double>()) << a;
        EXPECT_EQ(after[knob].is_string() ? after[knob].get<std::string>() : after[knob].dump(), a.substr(a.find('=') + 1)) << a;
    }
    // Nothing else changed: the effects' switches and the other knobs are the user's.
    for (const auto& [knob, value] : before.items()) {
        bool named = false;
        for (const std::string& a : list) named |= a.rfind(knob + "=", 0) == 0;
        if (!named) EXPECT_EQ(after[knob], value) << knob;
    }
    EXPECT_EQ(to_json(reduced_settings(full))["effects"], to_json(full)["effects"]);
    // Reduced twice is reduced once: nothing is left to lower.
    EXPECT_TRUE(reductions(reduced_settings(full)).empty());
}

// The knob rows say what they are while the camera moves: each such value (and its condition) is
// one the knob accepts, so that a typo in a row fails here, not in the middle of a movement.
TEST(ViewerAdaptiveQuality, EveryKnobsMovingValueIsOneItTakes) {
    int rows = 0;
    for (const KnobInfo& info : knob_infos()) {
        if (info.moving.empty()) continue;
        ++rows;
        RenderSettings s;
        EXPECT_NO_THROW(apply_knob(s, info.name + "=" + info.moving)) << info.name;
        if (!info.moving_when.empty()) EXPECT_NO_THROW(apply_knob(s, info.moving_when)) << info.name;
    }
    EXPECT_GE(rows, 12);
}

TEST(ViewerAdaptiveQuality, ReducedSettingsNeverRaiseTheUsersKnobs) {
    // Knobs the user set lower than the reduction stay; gi.budget 0 (converge before the frame) stays.
    const RenderSettings full = viewer_settings({"ssao.samples=2", "rsm.gather=quarter", "shadows.pcss_taps=1", "gi.budget=0"});
    const nlohmann::json after = to_json(reduced_settings(full))["knobs"];
    EXPECT_EQ(after["ssao.samples"], 2);
    EXPECT_EQ(after["rsm.gather"], "quarter");
    EXPECT_EQ(after["shadows.pcss_taps"], 1);
    EXPECT_EQ(after["gi.budget"], 0);
    for (const std::string& a : reductions(full))
        for (const char* knob : {"ssao.samples=", "rsm.gather=", "shadows.pcss_taps=", "gi.budget="}) EXPECT_NE(a.rfind(knob, 0), 0u) << a;
    // Depth peeling's layers are lowered only when peeling is the mode (else the knob does nothing).
    const auto names_layers = [](const RenderSettings& s) {
        for (const std::string& a : reductions(s))
            if (a.rfind("transparency.layers=", 0) == 0) return true;
        return false;
    };
    EXPECT_FALSE(names_layers(viewer_settings()));
    EXPECT_TRUE(names_layers(viewer_settings({"transparency.mode=peeling"})));
}

}  // namespace
}  // namespace candela::viewer
