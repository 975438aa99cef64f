// `candela bench error-budget`: the measurements behind --error-budget's model, the fit, and the
// evaluation of the model on measured scenes (docs/error-budget.md).
//   bench error-budget SCENE... --csv OUT.csv [--size WxH] [--spp N] [--frames N] [--trace-budgets E,...|none]   measure
//     (every raster candidate, and the tracer rung at each of the trace budgets: rows "trace@E")
//   bench error-budget --fit CSV... -o MODEL.json|MODEL.inc [--quantile Q] [--ridge R]   fit
//   bench error-budget --evaluate CSV... [--budget-model M] [--budgets E,E,...] [--markdown OUT.md]
#include "budget.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "accuracy/error_budget_measure.hpp"
#include "core/error.hpp"
#include "core/log.hpp"
#include "render/program_cache.hpp"

namespace candela::cli {
namespace fs = std::filesystem;

namespace {

const char* kBudgetCsvHeader =
    "scene,candidate,error,frame_ms,time_ratio,light_ms,reference_noise,reference_spp,reference_ms,nonfinite,"
    "indirect,coverage,punctual,shadowed,emissive,environment,metal,transmission,blend";

// --budgets / --trace-budgets E,E,... (default 0.01,0.03,0.1; "none": no budget).
std::vector<double> budgets_option(const Parsed& p, const std::string& option) {
    std::vector<double> b;
    const std::string text = p.has(option) ? p.get(option) : "0.01,0.03,0.1";
    if (text == "none") return b;
    std::stringstream ss(text);
    std::string x;
    while (std::getline(ss, x, ',')) b.push_back(budget::parse_budget(option, x));
    return b;
}

// The CSV row of the tracer rung measured at budget E: "trace@E".
std::string trace_row_name(double e) { return "trace@" + format_number("%g", e); }

int budget_measure(const Parsed& p) {
    if (!p.has("--csv")) throw bad_input("bench error-budget needs --csv OUT.csv (or --fit / --evaluate)");
    const int spp = p.has("--spp") ? parse_int("--spp", p.get("--spp"), 2, 1 << 20) : 512;
    const int frames = p.has("--frames") ? parse_int("--frames", p.get("--frames"), 1, 1000) : 15;
    const std::vector<double> trace_budgets = budgets_option(p, "--trace-budgets");
    const fs::path csv = p.get("--csv");
    const bool fresh = !fs::exists(csv) || fs::file_size(csv) == 0;
    std::ofstream out(csv, std::ios::app);
    if (!out) throw bad_input("--csv " + csv.string() + ": cannot write");
    if (fresh) out << kBudgetCsvHeader << "\n";
    SceneSetup s0 = setup_scene(p, p.positional[0], 160, 120);
    ContextResult ctx = open_context(s0);
    if (!ctx.context) return static_cast<int>(ExitCode::no_gl);
    const ShaderLibrary shaders(s0.shader_dir);
    ProgramCache programs(shaders);
    int failed = 0;
    for (size_t i = 0; i < p.positional.size(); ++i) {
        const std::string& name = p.positional[i];
        try {
            SceneSetup s = i == 0 ? std::move(s0) : setup_scene(p, name, 160, 120);
            finish_lighting(s, shaders);
            s.options.programs = &programs;
            const budget::SceneMeasurement m = budget::measure_scene(s.scene, shaders, s.options, spp, frames, trace_budgets);
            const budget::SceneStats& st = m.stats;
            auto row = [&](const std::string& candidate, double error, double ms, std::size_t nonfinite) {
                out << name << ',' << candidate << ',' << format_number("%.6f", error) << ',' << format_number("%.3f", ms) << ','
                    << format_number("%.4f", m.light_ms > 0 ? ms / m.light_ms : 0.0) << ',' << format_number("%.3f", m.light_ms) << ','
                    << format_number("%.6f", m.reference.noise) << ',' << m.reference.spp << ',' << format_number("%.0f", m.reference.ms) << ','
                    << nonfinite << ',' << format_number("%.4f", st.indirect) << ',' << format_number("%.4f", st.coverage) << ','
                    << st.punctual << ',' << st.shadowed << ',' << st.emissive << ',' << st.environment << ',' << st.metal << ','
                    << st.transmission << ',' << st.blend << "\n";
            };
            for (const budget::CandidateResult& c : m.candidates)
                row(budget::ladder()[static_cast<size_t>(c.candidate)].name, c.error, c.ms, c.nonfinite);
            for (const budget::SceneMeasurement::TraceResult& t : m.traces) row(trace_row_name(t.budget), t.error, t.ms, t.nonfinite);
            out.flush();
            std::string line;
            for (const budget::CandidateResult& c : m.candidates) {
                line += ' ';
                line += format_number("%.4f", c.error);
            }
            for (const budget::SceneMeasurement::TraceResult& t : m.traces)
                line += "; trace@" + format_number("%g", t.budget) + " " + format_number("%.4f", t.error) + " (" + std::to_string(t.spp) + " spp, noise " +
                        format_number("%.4f", t.noise) + ")";
            std::printf("%-28s noise %.4f, reference %.0f ms, errors%s\n", name.c_str(), m.reference.noise, m.reference.ms, line.c_str());
            std::fflush(stdout);
        } catch (const Error& e) {
            ++failed;
            log::warn(name + ": not measured: " + e.what());
        }
    }
    return failed ? 1 : 0;
}

// Splits a CSV line at commas (the files this command writes: no quoting).
std::vector<std::string> csv_fields(const std::string& line) {
    std::vector<std::string> f;
    std::stringstream ss(line);
    std::string x;
    while (std::getline(ss, x, ',')) f.push_back(x);
    return f;
}

// Rows of measurement CSVs, with each row's reference noise.
struct MeasuredRow {
    budget::Sample sample;
    double noise = 0;
    double trace_budget = 0;  // > 0: the tracer rung measured at this budget (sample.candidate is -1)
};
std::vector<MeasuredRow> read_measurements(const std::vector<std::string>& files) {
    std::vector<MeasuredRow> rows;
    for (const std::string& file : files) {
        std::ifstream in(file);
        if (!in) throw bad_input(file + ": cannot read the measurements");
        std::string line;
        std::getline(in, line);
        if (line != kBudgetCsvHeader) throw bad_input(file + ": not a `bench error-budget --csv` file (its header differs)");
        int n = 1;
        while (std::getline(in, line)) {
            ++n;
            if (line.empty()) continue;
            const std::vector<std::string> f = csv_fields(line);
            if (f.size() != 19) throw bad_input(file + ":" + std::to_string(n) + ": expected 19 fields");
            MeasuredRow r;
            r.sample.scene = f[0];
            r.sample.candidate = budget::candidate_index(f[1]);
            if (f[1].rfind("trace@", 0) == 0) {
                try {
                    r.trace_budget = budget::parse_budget("trace", f[1].substr(6));
                } catch (const Error&) {
                    throw bad_input(file + ":" + std::to_string(n) + ": '" + f[1] + "' is not trace@E with E in (0, 1]");
                }
            } else if (r.sample.candidate < 0) {
                continue;  // a candidate this candela no longer has
            }
            try {
                r.sample.error = std::stod(f[2]);
                r.sample.time_ratio = std::stod(f[4]);
                r.noise = std::stod(f[6]);
                budget::SceneStats& s = r.sample.stats;
                s.indirect = std::stod(f[10]), s.coverage = std::stod(f[11]), s.punctual = std::stod(f[12]);
                s.shadowed = std::stod(f[13]), s.emissive = std::stod(f[14]), s.environment = std::stod(f[15]);
                s.metal = std::stod(f[16]), s.transmission = std::stod(f[17]), s.blend = std::stod(f[18]);
            } catch (const std::exception&) {
                throw bad_input(file + ":" + std::to_string(n) + ": a field is not a number");
            }
            if (std::stoul(f[9]) != 0) continue;  // non-finite pixels: not a measurement to fit
            rows.push_back(r);
        }
    }
    if (rows.empty()) throw bad_input("bench error-budget: no measurements in the given files");
    return rows;
}

// `--fit CSV...` / `--evaluate CSV...`: the option's value and the positional arguments after it
// (every CSV of a parallel measurement; the option parser keeps only the first as its value).
std::vector<std::string> csv_files(const Parsed& p, const std::string& option) {
    std::vector<std::string> files = p.all(option);
    files.insert(files.end(), p.positional.begin(), p.positional.end());
    return files;
}

int budget_fit(const Parsed& p) {
    if (!p.has("-o")) throw bad_input("bench error-budget --fit needs -o MODEL.json or MODEL.inc");
    budget::FitOptions o;
    if (p.has("--quantile")) o.quantile = parse_float("--quantile", p.get("--quantile"), 0.5f, 1.0f);
    if (p.has("--ridge")) o.ridge = parse_float("--ridge", p.get("--ridge"), 0.0f, 1e6f);
    std::vector<budget::Sample> samples;
    double noise_max = 0;
    for (const MeasuredRow& r : read_measurements(csv_files(p, "--fit")))
        if (r.trace_budget == 0) samples.push_back(r.sample), noise_max = std::max(noise_max, r.noise);  // the tracer has no model
    budget::Model m = budget::fit(samples, o);
    m.size = p.has("--size") ? p.get("--size") : "160x120";
    m.reference_spp = p.has("--spp") ? parse_int("--spp", p.get("--spp"), 1, 1 << 20) : 512;
    m.note = "fitted by `candela bench error-budget --fit` (tests/tools/fit_error_budget.sh) on " + std::to_string(m.scenes) +
             " scenes; largest reference noise " + format_number("%.4f", noise_max);
    const std::string text = to_json(m).dump(1);
    const fs::path out = p.get("-o");
    std::ofstream f(out);
    if (!f) throw bad_input("-o " + out.string() + ": cannot write");
    if (out.extension() == ".inc")
        f << "// The fitted error-budget model (error_budget.hpp), written by `candela bench error-budget --fit`\n"
             "// (tests/tools/fit_error_budget.sh): do not edit by hand.\nR\"json("
          << text << ")json\"\n";
    else
        f << text << "\n";
    std::printf("fitted %zu candidates on %d scenes (%.0f %% quantile of the left-out residuals as margin)\n", m.candidates.size(), m.scenes,
                100.0 * m.quantile);
    for (const budget::CandidateModel& c : m.candidates)
        std::printf("  %-16s %3d scenes  error margin x%.2f  time margin x%.2f\n", c.name.c_str(), c.samples, std::exp(c.error_margin),
                    std::exp(c.time_margin));
    return 0;
}

// A scene's name without the directories of this machine: the table goes into the docs.
std::string short_name(const std::string& scene) {
    return scene.rfind("generated:", 0) == 0 ? scene : fs::path(scene).filename().string();
}

// The choices the model makes on measured scenes, against what was measured there: the same as
// `render --error-budget E --verify` on each scene at the measured size, without rendering again.
int budget_evaluate(const Parsed& p) {
    const budget::Model model = p.has("--budget-model") ? budget::load_model(p.get("--budget-model")) : budget::builtin_model();
    const std::vector<MeasuredRow> rows = read_measurements(csv_files(p, "--evaluate"));
    const std::vector<double> budgets = budgets_option(p, "--budgets");
    std::map<std::string, std::map<int, MeasuredRow>> by_scene;
    std::map<std::string, std::vector<MeasuredRow>> traces;  // the tracer rung's rows per scene
    std::vector<std::string> order;
    for (const MeasuredRow& r : rows) {
        if (!by_scene.count(r.sample.scene) && !traces.count(r.sample.scene)) order.push_back(r.sample.scene);
        if (r.trace_budget > 0) traces[r.sample.scene].push_back(r);
        else by_scene[r.sample.scene][r.sample.candidate] = r;
    }
    // The tracer rung's row of a scene at budget e (the CSV prints E with %g).
    auto trace_row = [&](const std::string& scene, double e) -> const MeasuredRow* {
        for (const MeasuredRow& r : traces[scene])
            if (std::abs(r.trace_budget - e) <= 1e-9 * e) return &r;
        return nullptr;
    };
    const int def = budget::candidate_index("default");
    std::ostringstream md, misses;
    md << "| E | scenes | achieved <= E | share | default <= E | some raster candidate <= E | some candidate or the tracer <= E | traced (no raster candidate predicted within E) | median achieved | median time vs default | slower than default and less accurate |\n"
       << "|---|---|---|---|---|---|---|---|---|---|---|\n";
    std::ostringstream choices;
    bool all_pass = true;
    for (const double e : budgets) {
        int n = 0, pass = 0, unmet = 0, dominated = 0, default_pass = 0, reachable = 0, raster_reachable = 0;
        std::vector<double> achieved, speed;
        std::map<std::string, int> picked;
        for (const std::string& scene : order) {
            const auto& cands = by_scene[scene];
            if (cands.size() != budget::ladder().size()) continue;  // a scene not measured with every candidate
            const budget::SceneStats& stats = cands.begin()->second.sample.stats;
            const budget::Choice c = budget::choose(budget::predict(model, stats), e);
            const int chosen = c.predictions[static_cast<size_t>(c.chosen)].candidate;
            const MeasuredRow* traced = trace_row(scene, e);
            if (c.trace && !traced)
                throw bad_input(scene + ": the budget " + format_number("%g", e) + " chooses the tracer, which the given files did not measure there "
                                "(bench error-budget --trace-budgets)");
            const MeasuredRow& got = c.trace ? *traced : cands.at(chosen);
            const std::string chosen_name = c.trace ? std::string("trace") : budget::ladder()[static_cast<size_t>(chosen)].name;
            const double predicted = c.trace ? budget::kTraceNoiseShare * e : c.predictions[static_cast<size_t>(c.chosen)].error;
            const MeasuredRow& d = cands.at(def);
            ++n;
            ++picked[chosen_name];
            unmet += !c.met;
            const bool ok = got.sample.error <= e;
            default_pass += d.sample.error <= e;
            bool any = false;  // the ladder's ceiling: an oracle's share
            for (const auto& [index, row] : cands) any = any || row.sample.error <= e;
            raster_reachable += any;
            any = any || (traced && traced->sample.error <= e);
            reachable += any;
            pass += ok;
            achieved.push_back(got.sample.error);
            speed.push_back(got.sample.time_ratio / d.sample.time_ratio);
            const bool worse = got.sample.time_ratio > d.sample.time_ratio * 1.0 && got.sample.error > d.sample.error;
            dominated += worse;
            if (!ok || worse)
                misses << "| " << format_number("%g", e) << " | " << short_name(scene) << " | " << chosen_name << " | "
                       << format_number("%.4f", predicted) << " | " << format_number("%.4f", got.sample.error)
                       << " | " << format_number("%.4f", got.noise) << " | " << format_number("%.4f", d.sample.error) << " | "
                       << format_number("%.2f", got.sample.time_ratio / d.sample.time_ratio) << " | "
                       << (!ok ? (c.met ? "over E" : "over E (no raster candidate predicted within E)") : "") << (!ok && worse ? "; " : "")
                       << (worse ? "slower and less accurate than default" : "") << " |\n";
        }
        if (n == 0) throw bad_input("bench error-budget --evaluate: no scene was measured with every candidate");
        std::sort(achieved.begin(), achieved.end());
        std::sort(speed.begin(), speed.end());
        const double share = static_cast<double>(pass) / n;
        all_pass = all_pass && share >= 0.9 && dominated == 0;
        md << "| " << format_number("%g", e) << " | " << n << " | " << pass << " | " << format_number("%.0f %%", 100.0 * share) << " | " << default_pass << " | " << raster_reachable << " | " << reachable << " | " << unmet
           << " | " << format_number("%.4f", achieved[achieved.size() / 2]) << " | x" << format_number("%.2f", speed[speed.size() / 2]) << " | "
           << dominated << " |\n";
        choices << "| " << format_number("%g", e) << " |";
        for (const budget::Candidate& cand : budget::ladder()) choices << " " << (picked.count(cand.name) ? picked[cand.name] : 0) << " |";
        choices << " " << (picked.count("trace") ? picked["trace"] : 0) << " |\n";
    }
    std::ostringstream all;
    all << md.str() << "\nChosen candidates (scenes per budget):\n\n| E |";
    for (const budget::Candidate& cand : budget::ladder()) all << " " << cand.name << " |";
    all << " trace |\n|---|";
    for (size_t i = 0; i <= budget::ladder().size(); ++i) all << "---|";
    all << "\n" << choices.str();
    const std::string miss_text = misses.str();
    all << "\nMisses (achieved error above E, or slower than the default and less accurate):\n\n";
    if (miss_text.empty()) all << "none\n";
    else
        all << "| E | scene | chosen | predicted | achieved | reference noise | default's error | time / default's | why |\n"
               "|---|---|---|---|---|---|---|---|---|\n"
            << miss_text;
    std::printf("%s", all.str().c_str());
    if (p.has("--markdown")) {
        std::ofstream f(p.get("--markdown"));
        if (!f) throw bad_input("--markdown " + p.get("--markdown") + ": cannot write");
        f << all.str();
    }
    std::printf("\ngoal (at least 90 %% within E at every E, never slower than the default and less accurate): %s\n",
                all_pass ? "met" : "not met");
    return 0;
}

}  // namespace

int bench_error_budget(const Args& args) {
    std::vector<std::string> with_value = kSceneSetupOptions;
    with_value.insert(with_value.end(), {"--csv", "--spp", "--fit", "--evaluate", "-o", "--quantile", "--ridge", "--budgets", "--trace-budgets",
                                         "--budget-model", "--markdown"});
    const Parsed p = parse(args, with_value, kSceneSetupFlags);
    if (p.has("--fit")) return budget_fit(p);
    if (p.has("--evaluate")) return budget_evaluate(p);
    if (p.positional.empty()) throw bad_input("bench error-budget needs SCENE... --csv OUT.csv, --fit CSV... or --evaluate CSV...");
    return budget_measure(p);
}

}  // namespace candela::cli
