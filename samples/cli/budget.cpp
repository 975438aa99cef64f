// --error-budget: the choice of settings for a budget (engine/accuracy/error_budget.hpp).
#include "budget.hpp"

#include <algorithm>
#include <cstdio>

#include "accuracy/error_budget_measure.hpp"
#include "core/error.hpp"
#include "render/gpu_scene.hpp"
#include "render/settings.hpp"
#include "rt/view_light.hpp"

namespace candela::cli {

const std::vector<std::string> kBudgetOptions = {"--error-budget", "--budget-model"};

std::optional<BudgetRequest> budget_request(const Parsed& p) {
    if (!p.has("--error-budget")) {
        if (p.has("--budget-model")) throw bad_input("--budget-model goes with --error-budget E");
        return std::nullopt;
    }
    BudgetRequest r;
    r.budget = budget::parse_budget("--error-budget", p.get("--error-budget"));
    if (p.has("--effects"))
        throw bad_input("--error-budget chooses the effects and their knobs: leave out --effects (--set still applies over the choice)");
    if (p.has("--budget-model")) {
        r.model = budget::load_model(p.get("--budget-model"));
        r.model_label = p.get("--budget-model");
    } else {
        r.model = budget::builtin_model();
        r.model_label = "built-in";
    }
    return r;
}

namespace {

std::string describe_prediction(const budget::Prediction& p) {
    const budget::Candidate& c = budget::ladder()[static_cast<size_t>(p.candidate)];
    return c.name + " (" + c.summary() + "): predicted error " + format_number("%.4f", p.error) + ", time x" +
           format_number("%.2f", p.time) + " speed of light";
}

}  // namespace

budget::Choice choose_for_scene(const BudgetRequest& r, const Scene& scene, const ShaderLibrary& shaders, const std::string& camera,
                                int width, int height, bool all_candidates, std::string& text) {
    const float aspect = static_cast<float>(width) / static_cast<float>(height);
    const budget::SceneStats stats = budget::scene_stats(scene, shaders, with_lens(scene.select_camera(camera, aspect), RenderSettings{}), aspect);
    std::vector<budget::Prediction> predictions = budget::predict(r.model, stats);
    // Caustics: no raster candidate draws them, so what the image loses without them is a floor
    // of every raster candidate's error (view_light.hpp, measure_caustics).
    std::string caustics_line;
    if (can_have_caustics(scene)) {
        try {
            GpuScene gpu(scene);
            const Caustics k = measure_caustics(shaders, scene, gpu, scene.select_camera(camera, aspect), aspect);
            for (budget::Prediction& pr : predictions) pr.error = std::max(pr.error, k.display_error);
            caustics_line = "error budget caustics: " + k.text() + "; every raster candidate's predicted error is at least " +
                            format_number("%.4f", k.display_error) + "\n";
        } catch (const Error& error) {
            if (error.code() == ExitCode::internal) throw;
        }
    }
    const budget::Choice c = budget::choose(predictions, r.budget);
    const budget::Model& m = r.model;
    text.clear();
    auto line = [&text](const char* format, auto... args) {
        char buf[1024];
        std::snprintf(buf, sizeof buf, format, args...);
        text += buf;
    };
    line("error budget: %.4g (mean |display difference| over 4x4 blocks against --raytrace path; model %s, fitted on %d scenes at %s, %.0f %% quantile)\n",
                 r.budget, r.model_label.c_str(), m.scenes, m.size.empty() ? "?" : m.size.c_str(), 100.0 * m.quantile);
    line("error budget statistics: indirect %.3f, coverage %.3f, punctual %g, shadowed %g, emissive %g, environment %g, metal %g, transmission %g, blend %g\n",
                 stats.indirect, stats.coverage, stats.punctual, stats.shadowed, stats.emissive, stats.environment, stats.metal,
                 stats.transmission, stats.blend);
    text += caustics_line;
    if (all_candidates) {
        line("error budget candidates (%zu):\n", c.predictions.size() + 1);
        for (size_t i = 0; i < c.predictions.size(); ++i) {
            const budget::Prediction& p = c.predictions[i];
            const std::string verdict = static_cast<int>(i) == c.chosen && !c.trace ? "chosen"
                                        : p.error > r.budget            ? "over the budget"
                                                                        : "within the budget, slower";
            line("  %-16s predicted error %.4f  time x%.2f speed of light  %s\n",
                         budget::ladder()[static_cast<size_t>(p.candidate)].name.c_str(), p.error, p.time, verdict.c_str());
        }
        line("  %-16s noise estimated while tracing, at most %.4f by %d spp  %s\n", "trace", budget::kTraceNoiseShare * r.budget,
             budget::kTraceMaxSpp, c.trace ? "chosen" : "not needed (a raster candidate is predicted within the budget)");
    }
    const budget::Prediction& chosen = c.predictions[static_cast<size_t>(c.chosen)];
    if (c.met)
        line("chosen: %s <= %.4g\n", describe_prediction(chosen).c_str(), r.budget);
    else
        line("chosen: the path tracer (--raytrace path): no raster candidate is predicted within the budget %.4g; it traces in "
             "rounds of doubling samples (%d to %d spp) until its own noise estimate is at most %.4g (half the budget)\n",
             r.budget, budget::kTraceMinSpp, budget::kTraceMaxSpp, budget::kTraceNoiseShare * r.budget);
    if (!c.met)
        line("runner-up: %s; rejected: predicted error above %.4g (it is the most accurate raster candidate)\n",
             describe_prediction(chosen).c_str(), r.budget);
    else if (c.runner_up >= 0)
        line("runner-up: %s; rejected: predicted error above %.4g\n", describe_prediction(c.predictions[static_cast<size_t>(c.runner_up)]).c_str(),
                     r.budget);
    else
        line("%s", "runner-up: none (no cheaper candidate)\n");
    return c;
}

RenderSettings budget_settings(const budget::Choice& c, const Parsed& p) {
    RenderSettings s = budget::candidate_settings(budget::ladder()[static_cast<size_t>(c.predictions[static_cast<size_t>(c.chosen)].candidate)]);
    if (p.has("--path")) apply_knob(s, "render.path=" + p.get("--path"));
    apply_knobs(s, p.all("--set"));
    return s;
}

}  // namespace candela::cli
