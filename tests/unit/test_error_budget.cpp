// Error-budgeted rendering (engine/accuracy/error_budget.hpp): the choice, its monotonicity in the
// budget, the fit and the model's data. Pure CPU logic (no GL).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "accuracy/error_budget.hpp"
#include "core/error.hpp"

namespace candela::budget {
namespace {

std::vector<Prediction> predictions(const std::vector<std::pair<double, double>>& error_time) {
    std::vector<Prediction> p;
    for (size_t i = 0; i < error_time.size(); ++i) p.push_back({static_cast<int>(i), error_time[i].first, error_time[i].second});
    return p;
}

TEST(ErrorBudget, PicksTheCheapestCandidateWithinTheBudget) {
    // Not in time order on purpose: the choice goes by predicted time, not by position.
    const auto p = predictions({{0.20, 1.0}, {0.02, 3.0}, {0.05, 1.5}, {0.01, 6.0}, {0.04, 2.0}});
    Choice c = choose(p, 0.045);
    EXPECT_TRUE(c.met);
    EXPECT_FALSE(c.trace);  // a raster candidate is predicted within: the tracer does not run
    EXPECT_EQ(c.chosen, 4);     // 0.04 at x2.0: cheaper than 0.02 at x3.0
    EXPECT_EQ(c.runner_up, 2);  // the next cheaper one, rejected: 0.05 > 0.045
    c = choose(p, 0.05);        // at the budget exactly: within it
    EXPECT_EQ(c.chosen, 2);
    EXPECT_EQ(c.runner_up, 0);
    c = choose(p, 1.0);
    EXPECT_EQ(c.chosen, 0);
    EXPECT_EQ(c.runner_up, -1);  // nothing is cheaper
    c = choose(p, 0.015);
    EXPECT_EQ(c.chosen, 3);
    EXPECT_EQ(c.runner_up, 1);
}

TEST(ErrorBudget, NoCandidateWithinTheBudgetChoosesTheMostAccurate) {
    const auto p = predictions({{0.20, 1.0}, {0.02, 3.0}, {0.015, 9.0}, {0.03, 2.0}});
    const Choice c = choose(p, 0.001);
    EXPECT_FALSE(c.met);
    EXPECT_TRUE(c.trace);  // the tracer renders the frame; chosen is the most accurate raster stand-in
    EXPECT_EQ(c.chosen, 2);
    EXPECT_EQ(c.runner_up, 1);
}

TEST(ErrorBudget, ASmallerBudgetNeverPicksACheaperCandidate) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> error(0.0, 0.2), time(1.0, 10.0);
    for (int trial = 0; trial < 200; ++trial) {
        std::vector<std::pair<double, double>> et;
        for (int i = 0; i < 9; ++i) et.push_back({error(rng), time(rng)});
        if (trial % 4 == 0) et[3].second = et[5].second;  // ties in time
        const auto p = predictions(et);
        double last_time = std::numeric_limits<double>::infinity(), last_error = -1;
        bool raster = false;
        for (double e = 0.001; e <= 0.25; e *= 1.2) {  // growing budgets: time never grows
            const Choice c = choose(p, e);
            // The tracer, slower than any raster frame, only below every budget a raster candidate meets.
            EXPECT_EQ(c.trace, !c.met);
            if (raster) EXPECT_FALSE(c.trace) << "trial " << trial << " budget " << e;
            raster = raster || !c.trace;
            const Prediction& got = p[static_cast<size_t>(c.chosen)];
            EXPECT_LE(got.time, last_time) << "trial " << trial << " budget " << e;
            if (got.time == last_time) EXPECT_GE(got.error, last_error - 1e-12);
            if (c.met) EXPECT_LE(got.error, e);
            last_time = got.time;
            last_error = got.error;
        }
    }
}

TEST(ErrorBudget, TheBuiltInModelIsMonotoneOnRandomStatistics) {
    const Model& m = builtin_model();
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (int trial = 0; trial < 100; ++trial) {
        SceneStats s;
        s.indirect = u(rng), s.coverage = u(rng), s.punctual = std::floor(4 * u(rng)), s.shadowed = u(rng) < 0.7;
        s.emissive = std::floor(3 * u(rng)), s.environment = u(rng) < 0.5, s.metal = u(rng) < 0.3;
        s.transmission = u(rng) < 0.3, s.blend = u(rng) < 0.2;
        const std::vector<Prediction> p = predict(m, s);
        ASSERT_EQ(p.size(), ladder().size());
        double last = -1;
        for (double e : {0.1, 0.03, 0.01, 0.003}) {  // shrinking budgets: time never falls
            const Choice c = choose(p, e);
            EXPECT_GE(p[static_cast<size_t>(c.chosen)].time, last);
            last = p[static_cast<size_t>(c.chosen)].time;
        }
    }
}

TEST(ErrorBudget, EveryRungOfTheLadderIsValidSettings) {
    EXPECT_GE(ladder().size(), 6u);
    EXPECT_LE(ladder().size(), 12u);
    bool has_default = false;
    for (const Candidate& c : ladder()) {
        EXPECT_NO_THROW(candidate_settings(c)) << c.name;
        has_default = has_default || (c.name == "default" && c.effects == "all" && c.knobs.empty());
        EXPECT_EQ(candidate_index(c.name), &c - ladder().data());
    }
    EXPECT_TRUE(has_default);
    EXPECT_EQ(candidate_index("no such rung"), -1);
}

TEST(ErrorBudget, TheBuiltInModelCoversTheLadder) {
    const Model& m = builtin_model();
    EXPECT_EQ(m.regressors, regressor_names());
    ASSERT_EQ(m.candidates.size(), ladder().size());
    for (size_t i = 0; i < ladder().size(); ++i) EXPECT_EQ(m.candidates[i].name, ladder()[i].name);
    // It survives a round trip through JSON (what --fit writes and --budget-model reads).
    const Model back = model_from_json(to_json(m));
    ASSERT_EQ(back.candidates.size(), m.candidates.size());
    EXPECT_EQ(back.candidates[3].error_weights, m.candidates[3].error_weights);
}

TEST(ErrorBudget, BadModelsAndBudgetsAreBadInput) {
    for (const char* text : {"-1", "abc", "0", "1.5", "nan", "0.03x", ""}) {
        try {
            parse_budget("--error-budget", text);
            ADD_FAILURE() << "accepted '" << text << "'";
        } catch (const Error& e) {
            EXPECT_EQ(e.code(), ExitCode::bad_input);
            EXPECT_NE(std::string(e.what()).find("--error-budget"), std::string::npos) << e.what();
        }
    }
    EXPECT_DOUBLE_EQ(parse_budget("--error-budget", "0.03"), 0.03);
    try {
        load_model("/nonexistent/model.json");
        ADD_FAILURE() << "a missing model file was read";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ExitCode::bad_input);
        EXPECT_NE(std::string(e.what()).find("--budget-model"), std::string::npos) << e.what();
    }
    nlohmann::json j = to_json(builtin_model());
    j["regressors"][1] = "something else";
    EXPECT_THROW(model_from_json(j), Error);
    j = to_json(builtin_model());
    j["candidates"][0]["error_weights"].push_back(1.0);
    EXPECT_THROW(model_from_json(j), Error);
}

TEST(ErrorBudget, RidgeSolveRecoversALinearLaw) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::vector<std::vector<double>> x;
    std::vector<double> y;
    for (int i = 0; i < 50; ++i) {
        const std::vector<double> row = {1.0, u(rng), u(rng), u(rng)};
        x.push_back(row);
        y.push_back(0.5 + 2.0 * row[1] - 1.0 * row[2] + 0.25 * row[3]);
    }
    const std::vector<double> w = ridge_solve(x, y, 0.0);
    ASSERT_EQ(w.size(), 4u);
    EXPECT_NEAR(w[0], 0.5, 1e-6);
    EXPECT_NEAR(w[1], 2.0, 1e-6);
    EXPECT_NEAR(w[2], -1.0, 1e-6);
    EXPECT_NEAR(w[3], 0.25, 1e-6);
    // A ridge shrinks the slopes, never the intercept's role: the mean stays fitted.
    const std::vector<double> shrunk = ridge_solve(x, y, 100.0);
    EXPECT_LT(std::abs(shrunk[1]), 2.0);
}

// The margin is the left-out residuals' quantile: on fresh scenes drawn from the same law, the
// predicted bound holds about as often as the quantile says.
TEST(ErrorBudget, TheFittedBoundHoldsOnFreshScenes) {
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::normal_distribution<double> noise(0.0, 0.3);
    auto draw = [&](int n, const std::string& prefix) {
        std::vector<Sample> out;
        for (int i = 0; i < n; ++i) {
            SceneStats s;
            s.indirect = u(rng), s.coverage = u(rng), s.shadowed = u(rng) < 0.5, s.transmission = u(rng) < 0.3;
            const double law = -4.0 + 2.0 * s.indirect + 0.7 * s.transmission;
            for (size_t c = 0; c < ladder().size(); ++c)
                out.push_back({prefix + std::to_string(i), static_cast<int>(c), s,
                               std::exp(law - 0.2 * static_cast<double>(c) + noise(rng)) - kErrorOffset, 1.0 + static_cast<double>(c)});
        }
        return out;
    };
    const Model m = fit(draw(80, "fit"), {0.9, 0.1});
    ASSERT_EQ(m.candidates.size(), ladder().size());
    int held = 0, total = 0;
    for (const Sample& s : draw(200, "new")) {
        const Prediction p = predict(m, s.stats)[static_cast<size_t>(s.candidate)];
        held += s.error <= p.error;
        ++total;
        EXPECT_NEAR(p.time, s.time_ratio, 0.05 * s.time_ratio);
    }
    const double share = static_cast<double>(held) / total;
    EXPECT_GT(share, 0.84);
    EXPECT_LT(share, 0.96);  // a margin that is not needlessly wide either
}

}  // namespace
}  // namespace candela::budget
