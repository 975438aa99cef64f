#pragma once
// Error-budgeted rendering (docs/error-budget.md): for a scene and view, the cheapest of a small
// ladder of settings whose predicted error against `--raytrace path` is at most a budget E.
//
// The error is the block metric of block_agreement (image/image.hpp): the mean absolute
// difference of display values over 4x4 blocks. Per candidate of the ladder, a fitted model
// predicts from cheap statistics of the scene (read before rendering: the indirect-light
// estimate of effects/gi/estimate.hpp, light and material counts, the scene features) an upper
// quantile of that error and the frame time as a ratio to the scene's speed-of-light frame.
// The model is fitted on measured scenes (`candela bench error-budget`) and compiled in
// (error_budget_model.inc); a JSON file of the same form can replace it.
//
// The parts that need GL (statistics, measuring, verifying) are in error_budget_measure.hpp; this
// header is plain logic and data.
#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "render/settings.hpp"

namespace candela::budget {

// The statistics a prediction reads, each a number; names in kStatNames order.
struct SceneStats {
    double indirect = 0;      // estimated indirect share of the seen surfaces' light [0, 1]
    double coverage = 0;      // share of the estimate's pixels that see a surface [0, 1]
    double punctual = 0;      // punctual lights
    double shadowed = 0;      // 1: some light casts shadows (the shadows effect is called for)
    double emissive = 0;      // emissive primitives (raster area lights)
    double environment = 0;   // 1: an environment lights the scene
    double metal = 0;         // 1: smooth metal calls for reflection probes
    double transmission = 0;  // 1: transmissive materials
    double blend = 0;         // 1: BLEND materials
};
// The regressors of the linear models: 1, then functions of the statistics (counts as log2(1+n)).
std::vector<double> regressors(const SceneStats& s);
const std::vector<std::string>& regressor_names();
nlohmann::json to_json(const SceneStats& s);
SceneStats stats_from_json(const nlohmann::json& j);

// One rung of the ladder: --effects and --set over the default settings.
struct Candidate {
    std::string name;
    std::string effects;              // an --effects value ("all", "none", "shadows,transparency")
    std::vector<std::string> knobs;   // --set assignments
    std::string summary() const;      // "--effects all --set a=b ..."
};
// The ladder, cheapest first in intent (the selector orders by predicted time, not by this order);
// "default" is the default settings.
const std::vector<Candidate>& ladder();
// Index of the candidate `name` in ladder(), or -1.
int candidate_index(const std::string& name);
// The default settings with the candidate's switches and knobs.
RenderSettings candidate_settings(const Candidate& c);

// Per candidate: ln(error + kErrorOffset) and ln(time ratio) linear in regressors().
constexpr double kErrorOffset = 0.003;
struct CandidateModel {
    std::string name;
    std::vector<double> error_weights, time_weights;  // one per regressor
    double error_margin = 0;  // added to ln(error + offset): the quantile of the left-out residuals
    double time_margin = 0;   // the same for time (informative; predictions use the median)
    int samples = 0;          // fitted scenes
};
struct Model {
    std::vector<std::string> regressors;  // must equal regressor_names()
    std::vector<CandidateModel> candidates;
    double quantile = 0.95;   // of the left-out residuals the margins are
    double ridge = 0;         // the fit's ridge weight
    std::string size;         // render size of the fitting data ("160x120")
    int reference_spp = 0;
    int scenes = 0;
    std::string note;         // how it was made
};
Model model_from_json(const nlohmann::json& j);  // throws bad_input naming what is wrong
nlohmann::json to_json(const Model& m);
const Model& builtin_model();
// Reads a model file (--budget-model FILE); throws bad_input naming the option and the file.
Model load_model(const std::filesystem::path& file);

struct Prediction {
    int candidate = -1;   // index in ladder()
    double error = 0;     // predicted upper quantile of the block error
    double time = 0;      // predicted frame time / speed-of-light frame time
};
std::vector<Prediction> predict(const Model& m, const SceneStats& s);

struct Choice {
    std::vector<Prediction> predictions;  // every candidate, in ladder order
    int chosen = -1;      // index into predictions
    int runner_up = -1;   // the next cheaper candidate than the chosen one (rejected: its error > E), or -1
    bool met = false;     // some candidate is predicted within the budget; else chosen is the most accurate
    // No raster candidate is predicted within the budget: the path tracer renders the frame, in
    // rounds until its own noise estimate is within kTraceNoiseShare * budget (TraceRung,
    // error_budget_measure.hpp). `chosen` stays the most accurate raster candidate: what a
    // command that must draw a raster frame (bench frame) uses instead.
    bool trace = false;
};

// The tracer rung. The path tracer is unbiased (its tests hold it to closed forms), so its error
// against the converged image is its noise, which two independent halves estimate while it
// renders. The target is half the budget: against a reference with its own noise n the achieved
// error is about sqrt((E/2)^2 + n^2), within E while n < 0.87 E. At least kTraceMinSpp samples
// (a few samples can miss rare paths in both halves and understate the noise), at most
// kTraceMaxSpp (then the budget is not promised).
constexpr double kTraceNoiseShare = 0.5;
constexpr int kTraceMinSpp = 64;
constexpr int kTraceMaxSpp = 4096;
// The cheapest (by predicted time; ties: smaller predicted error) candidate whose predicted error
// is at most `budget`; none: the most accurate raster candidate, and the frame is traced (trace).
// Pure logic: a smaller budget never picks a cheaper candidate than a larger one (the tracer is
// slower than every raster candidate on every measured scene).
Choice choose(const std::vector<Prediction>& predictions, double budget);

// The budget as given to --error-budget: a number in (0, 1]; throws bad_input naming the option.
double parse_budget(const std::string& option, const std::string& text);

// --- Fitting -------------------------------------------------------------------------------
// One measured (scene, candidate): what `bench error-budget` writes, one CSV row each.
struct Sample {
    std::string scene;
    int candidate = -1;
    SceneStats stats;
    double error = 0;         // block error against the path reference
    double time_ratio = 0;    // frame time / speed-of-light frame time
};
struct FitOptions {
    double quantile = 0.95;
    double ridge = 0.5;
};
// Ridge regression per candidate in log space; margins from leave-one-out residuals.
Model fit(const std::vector<Sample>& samples, const FitOptions& o);

// Least squares with a ridge on every weight but the first (the intercept): exposed for tests.
std::vector<double> ridge_solve(const std::vector<std::vector<double>>& x, const std::vector<double>& y, double ridge);

}  // namespace candela::budget
