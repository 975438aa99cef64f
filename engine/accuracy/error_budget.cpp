#include "accuracy/error_budget.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>

#include "core/error.hpp"

namespace candela::budget {
namespace fs = std::filesystem;

namespace {

double log_count(double n) { return std::log2(1.0 + std::max(0.0, n)); }

// The quantile q of `v` (linear interpolation between order statistics).
double quantile_of(std::vector<double> v, double q) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    const double at = q * static_cast<double>(v.size() - 1);
    const size_t lo = static_cast<size_t>(std::floor(at));
    const size_t hi = std::min(v.size() - 1, lo + 1);
    return v[lo] + (v[hi] - v[lo]) * (at - static_cast<double>(lo));
}

double dot(const std::vector<double>& a, const std::vector<double>& b) {
    double s = 0;
    for (size_t i = 0; i < a.size() && i < b.size(); ++i) s += a[i] * b[i];
    return s;
}

}  // namespace

// --- Statistics ------------------------------------------------------------------------------

const std::vector<std::string>& regressor_names() {
    static const std::vector<std::string> names = {"intercept", "indirect",    "coverage", "log2_punctual", "shadowed",
                                                   "log2_emissive", "environment", "metal", "transmission", "blend"};
    return names;
}

std::vector<double> regressors(const SceneStats& s) {
    return {1.0,        s.indirect,    s.coverage, log_count(s.punctual), s.shadowed, log_count(s.emissive),
            s.environment, s.metal, s.transmission, s.blend};
}

nlohmann::json to_json(const SceneStats& s) {
    return {{"indirect", s.indirect}, {"coverage", s.coverage},       {"punctual", s.punctual},
            {"shadowed", s.shadowed}, {"emissive", s.emissive},       {"environment", s.environment},
            {"metal", s.metal},       {"transmission", s.transmission}, {"blend", s.blend}};
}

SceneStats stats_from_json(const nlohmann::json& j) {
    SceneStats s;
    s.indirect = j.value("indirect", 0.0);
    s.coverage = j.value("coverage", 0.0);
    s.punctual = j.value("punctual", 0.0);
    s.shadowed = j.value("shadowed", 0.0);
    s.emissive = j.value("emissive", 0.0);
    s.environment = j.value("environment", 0.0);
    s.metal = j.value("metal", 0.0);
    s.transmission = j.value("transmission", 0.0);
    s.blend = j.value("blend", 0.0);
    return s;
}

// --- The ladder ------------------------------------------------------------------------------

std::string Candidate::summary() const {
    std::string s = "--effects " + effects;
    for (const std::string& k : knobs) s += " --set " + k;
    return s;
}

const std::vector<Candidate>& ladder() {
    // Built from the switches and knobs the accuracy sweeps measure one at a time. Effects the
    // scene does not call for never run, so a rung that switches them on costs nothing where they
    // are not needed. "default" is exactly the default settings.
    static const std::vector<Candidate> rungs = {
        {"no_effects", "none", {}},
        {"hard_shadows", "shadows,transparency", {"shadows.filter=hard", "shadows.resolution=512", "arealight.samples=1"}},
        {"lite", "shadows,transparency,reflections",
         {"shadows.filter=pcf", "shadows.pcf_size=3", "probe.resolution=64", "arealight.samples=2"}},
        {"reduced", "all",
         {"ssao.samples=8", "rsm.gather=quarter", "rsm.samples=16", "shadows.pcss_taps=8", "shadows.pcss_blocker_taps=4",
          "probe.resolution=64", "arealight.samples=2"}},
        {"default", "all", {}},
        {"default_no_ssao", "shadows,gi,reflections,rsm,transparency,motion_blur,dof", {}},
        {"gi_always", "all", {"gi.threshold=0"}},
        {"high", "shadows,gi,reflections,rsm,transparency,motion_blur,dof",
         {"gi.threshold=0", "gi.probes=12", "shadows.resolution=2048", "shadows.pcss_taps=64", "arealight.samples=8",
          "probe.resolution=256", "transparency.mode=peeling"}},
        {"max", "shadows,gi,reflections,rsm,transparency,motion_blur,dof",
         {"gi.threshold=0", "gi.probes=16", "gi.rays=256", "shadows.resolution=2048", "shadows.pcss_taps=64",
          "arealight.samples=16", "probe.resolution=256", "transparency.mode=peeling", "aa.samples=4"}},
    };
    return rungs;
}

int candidate_index(const std::string& name) {
    const auto& l = ladder();
    for (size_t i = 0; i < l.size(); ++i)
        if (l[i].name == name) return static_cast<int>(i);
    return -1;
}

RenderSettings candidate_settings(const Candidate& c) {
    RenderSettings s;
    apply_effects(s, c.effects);
    apply_knobs(s, c.knobs);
    return s;
}

// --- The model -------------------------------------------------------------------------------

namespace {

std::vector<double> weights_from(const nlohmann::json& j, const std::string& what, size_t n) {
    if (!j.is_array() || j.size() != n) throw bad_input("error-budget model: " + what + " must be an array of " + std::to_string(n) + " numbers");
    std::vector<double> w;
    for (const auto& v : j) {
        if (!v.is_number()) throw bad_input("error-budget model: " + what + " must hold numbers");
        w.push_back(v.get<double>());
    }
    return w;
}

}  // namespace

Model model_from_json(const nlohmann::json& j) {
    if (!j.is_object()) throw bad_input("error-budget model: not a JSON object");
    Model m;
    if (!j.contains("regressors") || !j["regressors"].is_array()) throw bad_input("error-budget model: no \"regressors\" list");
    for (const auto& r : j["regressors"]) m.regressors.push_back(r.get<std::string>());
    if (m.regressors != regressor_names())
        throw bad_input("error-budget model: its regressors are not this candela's (refit it: candela bench error-budget --fit)");
    m.quantile = j.value("quantile", 0.95);
    m.ridge = j.value("ridge", 0.0);
    m.size = j.value("size", std::string());
    m.reference_spp = j.value("reference_spp", 0);
    m.scenes = j.value("scenes", 0);
    m.note = j.value("note", std::string());
    if (!j.contains("candidates") || !j["candidates"].is_array()) throw bad_input("error-budget model: no \"candidates\" list");
    for (const auto& c : j["candidates"]) {
        CandidateModel cm;
        cm.name = c.value("name", std::string());
        if (candidate_index(cm.name) < 0) throw bad_input("error-budget model: unknown candidate '" + cm.name + "'");
        cm.error_weights = weights_from(c.value("error_weights", nlohmann::json()), cm.name + ".error_weights", m.regressors.size());
        cm.time_weights = weights_from(c.value("time_weights", nlohmann::json()), cm.name + ".time_weights", m.regressors.size());
        cm.error_margin = c.value("error_margin", 0.0);
        cm.time_margin = c.value("time_margin", 0.0);
        cm.samples = c.value("samples", 0);
        m.candidates.push_back(std::move(cm));
    }
    if (m.candidates.empty()) throw bad_input("error-budget model: no candidates");
    return m;
}

nlohmann::json to_json(const Model& m) {
    nlohmann::json j;
    j["regressors"] = m.regressors;
    j["quantile"] = m.quantile;
    j["ridge"] = m.ridge;
    j["size"] = m.size;
    j["reference_spp"] = m.reference_spp;
    j["scenes"] = m.scenes;
    j["note"] = m.note;
    j["candidates"] = nlohmann::json::array();
    for (const CandidateModel& c : m.candidates)
        j["candidates"].push_back({{"name", c.name},
                                   {"samples", c.samples},
                                   {"error_margin", c.error_margin},
                                   {"time_margin", c.time_margin},
                                   {"error_weights", c.error_weights},
                                   {"time_weights", c.time_weights}});
    return j;
}

const Model& builtin_model() {
    static const Model m = model_from_json(nlohmann::json::parse(
#include "accuracy/error_budget_model.inc"
        ));
    return m;
}

Model load_model(const fs::path& file) {
    std::ifstream in(file);
    if (!in) throw bad_input("--budget-model " + file.string() + ": cannot read the file");
    try {
        return model_from_json(nlohmann::json::parse(in));
    } catch (const nlohmann::json::exception& e) {
        throw bad_input("--budget-model " + file.string() + ": not JSON (" + e.what() + ")");
    } catch (const Error& e) {
        throw bad_input("--budget-model " + file.string() + ": " + e.what());
    }
}

std::vector<Prediction> predict(const Model& m, const SceneStats& s) {
    const std::vector<double> x = regressors(s);
    std::vector<Prediction> out;
    for (const CandidateModel& c : m.candidates) {
        Prediction p;
        p.candidate = candidate_index(c.name);
        p.error = std::max(0.0, std::exp(dot(c.error_weights, x) + c.error_margin) - kErrorOffset);
        p.time = std::exp(dot(c.time_weights, x));
        out.push_back(p);
    }
    return out;
}

Choice choose(const std::vector<Prediction>& predictions, double budget) {
    Choice c;
    c.predictions = predictions;
    auto cheaper = [&](int a, int b) {  // a before b: by time, then error, then ladder order
        const Prediction &pa = predictions[static_cast<size_t>(a)], &pb = predictions[static_cast<size_t>(b)];
        if (pa.time != pb.time) return pa.time < pb.time;
        if (pa.error != pb.error) return pa.error < pb.error;
        return a < b;
    };
    for (int i = 0; i < static_cast<int>(predictions.size()); ++i)
        if (predictions[static_cast<size_t>(i)].error <= budget && (c.chosen < 0 || cheaper(i, c.chosen))) c.chosen = i;
    c.met = c.chosen >= 0;
    c.trace = !c.met;
    if (!c.met) {
        for (int i = 0; i < static_cast<int>(predictions.size()); ++i) {
            const Prediction& p = predictions[static_cast<size_t>(i)];
            if (c.chosen < 0 || p.error < predictions[static_cast<size_t>(c.chosen)].error ||
                (p.error == predictions[static_cast<size_t>(c.chosen)].error && cheaper(i, c.chosen)))
                c.chosen = i;
        }
    }
    // The runner-up: the most expensive of the candidates cheaper than the chosen one. Each of
    // them was rejected (were it within the budget, it would have been chosen).
    if (c.chosen >= 0)
        for (int i = 0; i < static_cast<int>(predictions.size()); ++i)
            if (i != c.chosen && cheaper(i, c.chosen) && (c.runner_up < 0 || cheaper(c.runner_up, i))) c.runner_up = i;
    return c;
}

double parse_budget(const std::string& option, const std::string& text) {
    double v = 0;
    size_t used = 0;
    try {
        v = std::stod(text, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    if (used == 0 || used != text.size() || !std::isfinite(v))
        throw bad_input(option + " '" + text + "' must be a number (the mean display difference over 4x4 blocks, e.g. 0.03)");
    if (v <= 0.0 || v > 1.0) throw bad_input(option + " " + text + " is out of range: it must be in (0, 1] (e.g. 0.01, 0.03, 0.1)");
    return v;
}

// --- Fitting ---------------------------------------------------------------------------------

std::vector<double> ridge_solve(const std::vector<std::vector<double>>& x, const std::vector<double>& y, double ridge) {
    if (x.empty()) return {};
    const size_t k = x[0].size();
    // Normal equations (X'X + ridge D) w = X'y, D = diag(0, 1, ..., 1); Gaussian elimination
    // with partial pivoting (k is about ten).
    std::vector<std::vector<double>> a(k, std::vector<double>(k + 1, 0.0));
    for (size_t r = 0; r < x.size(); ++r)
        for (size_t i = 0; i < k; ++i) {
            for (size_t j = 0; j < k; ++j) a[i][j] += x[r][i] * x[r][j];
            a[i][k] += x[r][i] * y[r];
        }
    for (size_t i = 1; i < k; ++i) a[i][i] += ridge;
    for (size_t i = 0; i < k; ++i) a[i][i] += 1e-9;  // a regressor that is constant over the data
    for (size_t c = 0; c < k; ++c) {
        size_t pivot = c;
        for (size_t r = c + 1; r < k; ++r)
            if (std::abs(a[r][c]) > std::abs(a[pivot][c])) pivot = r;
        std::swap(a[c], a[pivot]);
        if (std::abs(a[c][c]) < 1e-300) continue;
        for (size_t r = 0; r < k; ++r) {
            if (r == c) continue;
            const double f = a[r][c] / a[c][c];
            for (size_t j = c; j <= k; ++j) a[r][j] -= f * a[c][j];
        }
    }
    std::vector<double> w(k, 0.0);
    for (size_t i = 0; i < k; ++i) w[i] = std::abs(a[i][i]) < 1e-300 ? 0.0 : a[i][k] / a[i][i];
    return w;
}

Model fit(const std::vector<Sample>& samples, const FitOptions& o) {
    Model m;
    m.regressors = regressor_names();
    m.quantile = o.quantile;
    m.ridge = o.ridge;
    std::map<std::string, bool> scenes;
    for (const Sample& s : samples) scenes[s.scene] = true;
    m.scenes = static_cast<int>(scenes.size());
    for (size_t ci = 0; ci < ladder().size(); ++ci) {
        std::vector<std::vector<double>> x;
        std::vector<double> ye, yt;
        for (const Sample& s : samples)
            if (s.candidate == static_cast<int>(ci)) {
                x.push_back(regressors(s.stats));
                ye.push_back(std::log(std::max(0.0, s.error) + kErrorOffset));
                yt.push_back(std::log(std::max(1e-3, s.time_ratio)));
            }
        if (x.size() < 3) continue;  // not measured: the candidate is left out of the model
        CandidateModel c;
        c.name = ladder()[ci].name;
        c.samples = static_cast<int>(x.size());
        c.error_weights = ridge_solve(x, ye, o.ridge);
        c.time_weights = ridge_solve(x, yt, o.ridge);
        // Leave-one-out residuals: what the model misses on a scene it was not fitted on.
        std::vector<double> re, rt;
        for (size_t leave = 0; leave < x.size(); ++leave) {
            std::vector<std::vector<double>> xs;
            std::vector<double> es, ts;
            for (size_t r = 0; r < x.size(); ++r)
                if (r != leave) xs.push_back(x[r]), es.push_back(ye[r]), ts.push_back(yt[r]);
            re.push_back(ye[leave] - dot(ridge_solve(xs, es, o.ridge), x[leave]));
            rt.push_back(yt[leave] - dot(ridge_solve(xs, ts, o.ridge), x[leave]));
        }
        c.error_margin = std::max(0.0, quantile_of(re, o.quantile));
        c.time_margin = std::max(0.0, quantile_of(rt, o.quantile));
        m.candidates.push_back(std::move(c));
    }
    if (m.candidates.empty()) throw bad_input("error-budget fit: no candidate has measurements of 3 scenes or more");
    return m;
}

}  // namespace candela::budget
