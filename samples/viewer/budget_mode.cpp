#include "budget_mode.hpp"

#include <cstdio>

#include "core/error.hpp"
#include "effect_status.hpp"

namespace candela::viewer {

std::optional<double> parse_budget_argument(const std::string& text) {
    if (text == "off") return std::nullopt;
    try {
        return budget::parse_budget("budget", text);
    } catch (const Error&) {
        throw bad_input("'budget' takes an error budget E in (0, 1] (e.g. 0.03) or off, not '" + text + "'");
    }
}

RenderSettings budget_settings(const budget::Choice& c, const std::vector<std::string>& set_knobs, const RenderSettings& current) {
    const budget::Prediction& p = c.predictions.at(static_cast<size_t>(c.chosen));
    RenderSettings s = budget::candidate_settings(budget::ladder().at(static_cast<size_t>(p.candidate)));
    apply_viewer_defaults(s, set_knobs);
    apply_knobs(s, set_knobs);
    s.path = current.path;
    return s;
}

namespace {

std::string describe(const budget::Prediction& p) {
    const budget::Candidate& c = budget::ladder()[static_cast<size_t>(p.candidate)];
    char numbers[96];
    std::snprintf(numbers, sizeof numbers, "predicted error %.4f, time x%.2f speed of light", p.error, p.time);
    return c.name + " (" + c.summary() + "): " + numbers;
}

std::string format_budget(double budget) {
    char b[32];
    std::snprintf(b, sizeof b, "%.4g", budget);
    return b;
}

}  // namespace

std::vector<std::string> choice_lines(const budget::Choice& c, double budget) {
    const std::string e = format_budget(budget);
    const budget::Prediction& chosen = c.predictions.at(static_cast<size_t>(c.chosen));
    if (c.trace)
        return {"chosen: the path tracer (reference mode path, shown as the reference): no raster candidate is predicted within "
                "the budget " + e + "; it refines the view between frames",
                "runner-up: " + describe(chosen) + "; rejected: predicted error above " + e +
                    " (it is the most accurate raster candidate: the raster frame under the reference renders at it)"};
    std::vector<std::string> lines = {"chosen: " + describe(chosen) + " <= " + e};
    if (c.runner_up >= 0)
        lines.push_back("runner-up: " + describe(c.predictions.at(static_cast<size_t>(c.runner_up))) + "; rejected: predicted error above " + e);
    else
        lines.push_back("runner-up: none (no cheaper candidate)");
    return lines;
}

BudgetApply BudgetMode::apply(const budget::Choice& c, double budget, const RenderSettings& settings, const RenderSettings& current,
                              const ReferenceView& reference) {
    if (!on_) before_ = current;
    on_ = true;
    budget_ = budget;
    choice_ = c;
    BudgetApply a{settings, reference};
    if (c.trace) {
        if (!tracing_) reference_before_ = reference;
        a.reference = ReferenceView{true, kTraceReferenceMode, kTraceReferenceView};
    } else if (tracing_) {
        a.reference = reference_before_;
    }
    tracing_ = c.trace;
    return a;
}

std::optional<BudgetApply> BudgetMode::off(const ReferenceView& reference) {
    if (!on_) return std::nullopt;
    BudgetApply a{before_, tracing_ ? reference_before_ : reference};
    on_ = tracing_ = false;
    choice_.reset();
    return a;
}

}  // namespace candela::viewer
