#pragma once
// The viewer's error budget (panel section "Error budget", script verb `budget E|off`,
// `candela view --error-budget E`; docs/error-budget.md): from the statistics of the current
// view, the cheapest candidate of the ladder predicted within E becomes the viewer's base
// settings (the ones adaptive quality lowers while the view moves). When no raster candidate is
// predicted within E, the reference mode traces the view (`path`, shown as the reference) and the
// raster frame under it renders at the most accurate raster candidate. Turning the budget off
// gives back the settings and the reference view from before.
//
// The choice is made when the budget is turned on, when E changes and on request, never on a
// camera move: the statistics cost a small trace.
//
// Plain logic (no GL): the viewer measures the statistics and applies what this returns.
#include <optional>
#include <string>
#include <vector>

#include "accuracy/error_budget.hpp"
#include "render/settings.hpp"

namespace candela::viewer {

// The script's `budget E|off` argument: nullopt for "off", else E, a number in (0, 1]. Throws
// bad_input saying what is wrong (the caller adds FILE:LINE).
std::optional<double> parse_budget_argument(const std::string& text);

// The reference mode's state the budget takes over while the tracer renders the frame.
struct ReferenceView {
    bool on = false;
    int mode = 0;  // index in Reference::kModes ("path" is 0)
    int view = 0;  // index in Reference::kViews ("reference" is 1)
    bool operator==(const ReferenceView&) const = default;
};
constexpr int kTraceReferenceMode = 0;  // path
constexpr int kTraceReferenceView = 1;  // reference

// The settings the viewer renders a choice at: the chosen candidate's (for the tracer: the most
// accurate raster candidate, Choice::chosen), then the viewer's interactive defaults and the
// command line's --set knobs over them (as `render` applies --set over its choice), and the
// render path of `current` (the candidates leave the path alone).
RenderSettings budget_settings(const budget::Choice& c, const std::vector<std::string>& set_knobs, const RenderSettings& current);

// The lines the log and the panel show for a choice, as `render --error-budget` words them:
// "chosen: ...", then "runner-up: ..." (or "runner-up: none ...").
std::vector<std::string> choice_lines(const budget::Choice& c, double budget);

// What the viewer renders at while the budget is on, or goes back to when it is turned off.
struct BudgetApply {
    RenderSettings settings;
    ReferenceView reference;
};

class BudgetMode {
public:
    bool on() const { return on_; }
    double budget() const { return budget_; }
    // Whether the tracer renders the frame (the last choice had no raster candidate within E).
    bool tracing() const { return tracing_; }
    const std::optional<budget::Choice>& choice() const { return choice_; }

    // A choice for `budget` (turning the budget on, a new E or a re-choice): `settings` is what
    // the choice renders at (budget_settings), `current` and `reference` what the viewer has
    // now. The first choice after off keeps `current` to give back; the first traced choice
    // keeps `reference`. Returns what to apply: the choice's settings, and the reference traced
    // (a traced choice) or given back (a raster choice after a traced one) or left as it is.
    BudgetApply apply(const budget::Choice& c, double budget, const RenderSettings& settings, const RenderSettings& current,
                      const ReferenceView& reference);
    // Turns the budget off: the settings from before it was on and, after a traced choice, the
    // reference view from before that. nullopt when it was off.
    std::optional<BudgetApply> off(const ReferenceView& reference);

private:
    bool on_ = false, tracing_ = false;
    double budget_ = 0.0;
    std::optional<budget::Choice> choice_;
    RenderSettings before_;
    ReferenceView reference_before_;
};

}  // namespace candela::viewer
