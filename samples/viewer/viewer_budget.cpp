// The viewer's error budget (budget_mode.hpp): the choice from the current view's statistics,
// applied as the base settings (and the reference mode when the tracer renders the frame). Its
// panel section is budget_ui (viewer_panel.cpp).
#include "viewer_internal.hpp"

#include <cstdio>

#include "accuracy/error_budget_measure.hpp"

namespace candela::viewer {
namespace {

void log_frame(int frame, const std::string& line) { log::info("viewer: frame " + std::to_string(frame) + ": " + line); }

std::string describe_reference(const ReferenceView& v) {
    if (!v.on) return std::string("off (show ") + Reference::kViews[v.view] + ")";
    return std::string(Reference::kModes[v.mode]) + ", show " + Reference::kViews[v.view];
}

}  // namespace

void Viewer::choose_budget(const Camera& camera, int w, int h) {
    budget_pending_ = false;
    const double e = budget_e_;
    const float aspect = h > 0 ? static_cast<float>(w) / static_cast<float>(h) : 1.0f;
    const auto t0 = Clock::now();
    budget::SceneStats stats;
    try {
        stats = budget::scene_stats(scene_, shaders_, with_lens(camera, settings_), aspect);
    } catch (const Error& err) {
        settings_error_ = std::string("error budget: ") + err.what();
        log::warn(settings_error_);
        return;
    }
    const double ms = ms_since(t0);
    const budget::Choice c = budget::choose(budget::predict(o_.budget_model, stats), e);
    char line[512];
    std::snprintf(line, sizeof line,
                  "statistics of this view (%.0f ms): indirect %.3f, coverage %.3f, punctual %g, shadowed %g, emissive %g, "
                  "environment %g, metal %g, transmission %g, blend %g",
                  ms, stats.indirect, stats.coverage, stats.punctual, stats.shadowed, stats.emissive, stats.environment, stats.metal,
                  stats.transmission, stats.blend);
    budget_stats_ = line;
    std::snprintf(line, sizeof line, "error budget %.4g (model %s, fitted on %d scenes at %s): ", e, o_.budget_model_label.c_str(),
                  o_.budget_model.scenes, o_.budget_model.size.empty() ? "?" : o_.budget_model.size.c_str());
    log_frame(frame_, line + budget_stats_);
    for (const std::string& l : choice_lines(c, e)) log_frame(frame_, l);

    const ReferenceView reference_now = reference_view();
    const BudgetApply a = budget_.apply(c, e, budget_settings(c, o_.set_knobs, settings_), settings_, reference_now);
    apply_settings(a.settings);
    if (!(a.reference == reference_now)) {
        set_reference_view(a.reference);
        log_frame(frame_, "error budget: reference " + describe_reference(a.reference) +
                              (c.trace ? " (the frame is traced: no raster candidate is predicted within the budget)"
                                       : " (as before the frame was traced)"));
    }
}

void Viewer::budget_off() {
    budget_pending_ = false;
    const ReferenceView reference_now = reference_view();
    const std::optional<BudgetApply> a = budget_.off(reference_now);
    if (!a) return;
    apply_settings(a->settings);
    set_reference_view(a->reference);
    log_frame(frame_, "error budget off: the settings from before it was on are back, reference " + describe_reference(a->reference));
}

}  // namespace candela::viewer
