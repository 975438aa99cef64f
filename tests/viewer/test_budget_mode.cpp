// The viewer's error budget (samples/viewer/budget_mode.hpp): the script argument's checks, the
// settings a choice renders at, the lines the log prints, and what turning the budget on, choosing
// again, tracing and turning it off give back.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "../../samples/viewer/budget_mode.hpp"
#include "../../samples/viewer/effect_status.hpp"
#include "core/error.hpp"

namespace candela::viewer {
namespace {

// A choice among the ladder's candidates with made-up predictions: `error_time` per candidate
// in ladder order (missing ones are far over any budget and slow).
budget::Choice budget_test_choice(const std::vector<std::pair<std::string, std::pair<double, double>>>& error_time, double e) {
    std::vector<budget::Prediction> p;
    for (size_t i = 0; i < budget::ladder().size(); ++i) p.push_back({static_cast<int>(i), 0.9, 50.0 + static_cast<double>(i)});
    for (const auto& [name, et] : error_time) {
        const int i = budget::candidate_index(name);
        EXPECT_GE(i, 0) << name;
        p[static_cast<size_t>(i)].error = et.first;
        p[static_cast<size_t>(i)].time = et.second;
    }
    return budget::choose(p, e);
}

nlohmann::json budget_test_knobs(const RenderSettings& s) { return to_json(s); }

TEST(ViewerBudget, TheScriptArgumentIsABudgetOrOff) {
    EXPECT_FALSE(parse_budget_argument("off").has_value());
    EXPECT_DOUBLE_EQ(*parse_budget_argument("0.1"), 0.1);
    EXPECT_DOUBLE_EQ(*parse_budget_argument("1"), 1.0);
    EXPECT_DOUBLE_EQ(*parse_budget_argument("1e-3"), 0.001);
    for (const char* bad : {"abc", "0", "-1", "1.5", "nan", "inf", "0.1x", "", "OFF"}) {
        try {
            parse_budget_argument(bad);
            ADD_FAILURE() << "'" << bad << "' was accepted";
        } catch (const Error& e) {
            EXPECT_EQ(e.code(), ExitCode::bad_input);
            EXPECT_EQ(std::string(e.what()), "'budget' takes an error budget E in (0, 1] (e.g. 0.03) or off, not '" + std::string(bad) + "'");
        }
    }
}

TEST(ViewerBudget, AChoiceRendersAtItsCandidateWithTheViewersDefaultsAndTheUsersKnobs) {
    const budget::Choice c = budget_test_choice({{"reduced", {0.03, 3.0}}, {"lite", {0.25, 1.8}}}, 0.1);
    ASSERT_FALSE(c.trace);
    ASSERT_EQ(budget::ladder()[static_cast<size_t>(c.predictions[static_cast<size_t>(c.chosen)].candidate)].name, "reduced");
    RenderSettings current;
    current.path = RenderPath::deferred;
    apply_knob(current, "ssao.samples=32");  // the settings before: replaced, but for the path
    const std::vector<std::string> set = {"ssao.bias=0.2"};
    const RenderSettings s = budget_settings(c, set, current);

    RenderSettings expected = budget::candidate_settings(budget::ladder()[static_cast<size_t>(budget::candidate_index("reduced"))]);
    apply_viewer_defaults(expected, set);
    apply_knobs(expected, set);
    expected.path = RenderPath::deferred;
    EXPECT_EQ(budget_test_knobs(s), budget_test_knobs(expected));
    const nlohmann::json knobs = to_json(s)["knobs"];
    EXPECT_EQ(knobs["ssao.samples"], 8);    // the candidate's
    EXPECT_EQ(knobs["ssao.bias"], 0.2f);    // the user's --set, over the choice
    EXPECT_EQ(knobs["gi.budget"], to_json(expected)["knobs"]["gi.budget"]);
    EXPECT_NE(knobs["gi.budget"], 0);  // the viewer's interactive GI budget, not a still's
    // A --set gi.budget stays the user's.
    EXPECT_EQ(to_json(budget_settings(c, {"gi.budget=0"}, current))["knobs"]["gi.budget"], 0);
    // The tracer's choice renders the raster frame at the most accurate raster candidate.
    const budget::Choice t = budget_test_choice({{"reduced", {0.03, 3.0}}, {"max", {0.019, 5.6}}}, 0.008);
    ASSERT_TRUE(t.trace);
    EXPECT_EQ(budget_test_knobs(budget_settings(t, {}, current)),
              budget_test_knobs([&] {
                  RenderSettings m = budget::candidate_settings(budget::ladder()[static_cast<size_t>(budget::candidate_index("max"))]);
                  apply_viewer_defaults(m, {});
                  m.path = RenderPath::deferred;
                  return m;
              }()));
}

TEST(ViewerBudget, TheLinesSayWhatWasChosenAndWhatWasRejected) {
    std::vector<std::string> l = choice_lines(budget_test_choice({{"reduced", {0.029, 2.99}}, {"lite", {0.2554, 1.8}}}, 0.1), 0.1);
    ASSERT_EQ(l.size(), 2u);
    EXPECT_EQ(l[0].rfind("chosen: reduced (--effects all", 0), 0u) << l[0];
    EXPECT_NE(l[0].find("predicted error 0.0290, time x2.99 speed of light <= 0.1"), std::string::npos) << l[0];
    EXPECT_EQ(l[1].rfind("runner-up: lite (", 0), 0u) << l[1];
    EXPECT_NE(l[1].find("predicted error 0.2554, time x1.80 speed of light; rejected: predicted error above 0.1"), std::string::npos) << l[1];

    l = choice_lines(budget_test_choice({{"no_effects", {0.02, 0.9}}}, 0.05), 0.05);
    ASSERT_EQ(l.size(), 2u);
    EXPECT_EQ(l[0].rfind("chosen: no_effects (", 0), 0u) << l[0];
    EXPECT_EQ(l[1], "runner-up: none (no cheaper candidate)");

    l = choice_lines(budget_test_choice({{"max", {0.0189, 5.6}}}, 0.008), 0.008);
    ASSERT_EQ(l.size(), 2u);
    EXPECT_EQ(l[0].rfind("chosen: the path tracer (reference mode path, shown as the reference): no raster candidate is predicted within the budget 0.008", 0), 0u) << l[0];
    EXPECT_EQ(l[1].rfind("runner-up: max (", 0), 0u) << l[1];
    EXPECT_NE(l[1].find("rejected: predicted error above 0.008 (it is the most accurate raster candidate"), std::string::npos) << l[1];
}

TEST(ViewerBudget, OffGivesBackTheSettingsFromBeforeItWasOn) {
    BudgetMode m;
    EXPECT_FALSE(m.on());
    EXPECT_FALSE(m.off({}).has_value());  // off while off: nothing to give back

    RenderSettings user, chosen_a, chosen_b;
    apply_knob(user, "ssao.samples=24");
    apply_knob(chosen_a, "ssao.samples=8");
    apply_knob(chosen_b, "ssao.samples=12");
    const ReferenceView ref{true, 2, 3};  // the user's reference: whitted, shown as a flip

    const budget::Choice raster = budget_test_choice({{"reduced", {0.03, 3.0}}}, 0.1);
    BudgetApply a = m.apply(raster, 0.1, chosen_a, user, ref);
    EXPECT_TRUE(m.on());
    EXPECT_FALSE(m.tracing());
    EXPECT_DOUBLE_EQ(m.budget(), 0.1);
    ASSERT_TRUE(m.choice().has_value());
    EXPECT_EQ(budget_test_knobs(a.settings), budget_test_knobs(chosen_a));
    EXPECT_EQ(a.reference, ref);  // a raster choice leaves the reference alone
    // A new E: the viewer's settings are now the choice's; what is given back stays the user's.
    a = m.apply(raster, 0.05, chosen_b, chosen_a, ref);
    EXPECT_EQ(budget_test_knobs(a.settings), budget_test_knobs(chosen_b));
    EXPECT_DOUBLE_EQ(m.budget(), 0.05);
    const std::optional<BudgetApply> back = m.off(ref);
    ASSERT_TRUE(back.has_value());
    EXPECT_EQ(budget_test_knobs(back->settings), budget_test_knobs(user));
    EXPECT_EQ(back->reference, ref);
    EXPECT_FALSE(m.on());
    EXPECT_FALSE(m.choice().has_value());
    EXPECT_FALSE(m.off(ref).has_value());
}

TEST(ViewerBudget, ATracedChoiceTakesTheReferenceAndGivesItBack) {
    BudgetMode m;
    RenderSettings user, chosen;
    apply_knob(user, "ssao.samples=24");
    const ReferenceView user_ref{false, 3, 2};  // off, ao mode, split
    const ReferenceView traced{true, kTraceReferenceMode, kTraceReferenceView};
    const budget::Choice raster = budget_test_choice({{"reduced", {0.03, 3.0}}}, 0.1);
    const budget::Choice trace = budget_test_choice({{"max", {0.019, 5.6}}}, 0.008);
    ASSERT_TRUE(trace.trace);

    // Raster, then traced: the reference is taken over (path, shown as the reference).
    m.apply(raster, 0.1, chosen, user, user_ref);
    BudgetApply a = m.apply(trace, 0.008, chosen, chosen, user_ref);
    EXPECT_TRUE(m.tracing());
    EXPECT_EQ(a.reference, traced);
    // Traced again (a re-choice): what was before the tracing stays what is given back.
    a = m.apply(trace, 0.008, chosen, chosen, traced);
    EXPECT_EQ(a.reference, traced);
    // A raster choice gives the reference back.
    a = m.apply(raster, 0.1, chosen, chosen, traced);
    EXPECT_FALSE(m.tracing());
    EXPECT_EQ(a.reference, user_ref);
    // Traced, then off: the settings and the reference from before.
    m.apply(trace, 0.008, chosen, chosen, user_ref);
    const std::optional<BudgetApply> back = m.off(traced);
    ASSERT_TRUE(back.has_value());
    EXPECT_EQ(back->reference, user_ref);
    EXPECT_EQ(budget_test_knobs(back->settings), budget_test_knobs(user));
    // Traced from the start (the budget turned on at a small E), then off.
    m.apply(trace, 0.008, chosen, user, user_ref);
    EXPECT_EQ(m.off(traced)->reference, user_ref);
}

}  // namespace
}  // namespace candela::viewer
