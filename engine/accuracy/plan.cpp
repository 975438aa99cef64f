#include "accuracy/plan.hpp"

#include <algorithm>
#include <filesystem>
#include <utility>

#include "accuracy/error_budget.hpp"
#include "core/error.hpp"
#include "render/effect_registry.hpp"
#include "render/features.hpp"
#include "render/settings.hpp"
#include "scene/generate.hpp"
#include "scene/gltf_loader.hpp"

namespace candela::accuracy {
namespace fs = std::filesystem;

namespace {

// The sweeps: every registered effect's own (effects/*/*_sweep.cpp), in registry order, then the
// three that belong to no effect. Each reading says what the error is made of; the numbers come
// from the run.
std::vector<AccuracySweep> make_sweeps(bool quick) {
    std::vector<AccuracySweep> sweeps;
    for (const Effect* e : effect_registry())
        for (AccuracySweep& s : e->accuracy_sweeps(quick)) sweeps.push_back(std::move(s));
    {
        AccuracySweep s;
        s.effect = "forward_deferred";
        s.compared = "time only: the whole frame without effects, forward vs deferred, by light count (generated:lights:N)";
        s.reading = "Forward shading loops over every light per fragment (overdraw included); deferred pays the "
                    "G-buffer once and culls lights per 16x16 tile. The crossing point sets deferred.auto_lights.";
        sweeps.push_back(s);
    }
    {
        AccuracySweep s;
        s.effect = "material_layers";
        s.scene = "generated:materials";
        s.reference = AccuracySweep::Reference{rt::Mode::path, quick ? 32 : 256};
        s.reference->jitter = 1;
        s.compared = "the forward raster with and without the material extensions' layers (`render.material_layers`) vs "
                     "`--raytrace path`, which always shades them";
        s.reading = "The layers' lobes are the tracer's own; the raster lights them by the sun exactly and by the sky "
                    "through the split sum (the coat by its own prefiltered reflection, the sheen by irradiance, "
                    "anisotropy by one bent normal). Off shows what dropping them costs in error and saves in time.";
        s.variants.push_back({"layers", "none", {"render.material_layers=1"}});
        s.variants.push_back({"base BRDF only", "none", {"render.material_layers=0"}});
        s.shipped = "layers";
        s.needed = [](const Features& f) { return f.scene.material_layers.needed; };
        sweeps.push_back(s);
    }
    if (!quick) {
        // --error-budget's ladder (error_budget.hpp) as hand-picked knob sets, and the budget's
        // choices for E = 0.01, 0.03 and 0.1 on this scene as points beside them ("budget:E" is
        // resolved where the tracer can measure the view: run.cpp). Not in --quick: the ladder's
        // GI rungs converge their probes before each frame, too slow for CI.
        AccuracySweep s;
        s.effect = "error_budget";
        s.scene = "cornell_box.gltf";
        s.reference = AccuracySweep::Reference{rt::Mode::path, 256};
        s.reference->jitter = 1;  // the box-filtered pixel: the reference --error-budget is measured against
        s.compared = "the candidates of `--error-budget`'s ladder (whole frames) and the budget's choice at E = 0.01, "
                     "0.03, 0.1 vs `--raytrace path`";
        s.reading = "The budget picks by a model's prediction of the block error (docs/error-budget.md), not by the "
                    "RMSE shown here; a choice sits on or near the front when the model ranks the candidates as the "
                    "measurement does.";
        for (const budget::Candidate& c : budget::ladder()) s.variants.push_back({c.name, c.effects, c.knobs});
        for (const char* e : {"0.01", "0.03", "0.1"}) s.variants.push_back({std::string("budget E=") + e, std::string("budget:") + e, {}});
        s.shipped = "default";
        s.needed = [](const Features&) { return true; };
        sweeps.push_back(s);
    }
    {
        AccuracySweep s;
        s.effect = "ray_tracer";
        s.scene = "cornell_box.gltf";
        s.compared = "`--raytrace path` at rising spp vs a high-spp render of itself: the price of the truth";
        s.reading = "Monte Carlo error falls as 1/sqrt(spp) while time grows linearly: each halving of the error "
                    "costs four times the time.";
        sweeps.push_back(s);
    }
    {
        AccuracySweep s;
        s.effect = "ray_tracer_depth";
        s.scene = "cornell_box.gltf";
        s.compared = "`--raytrace path --max-depth N` vs the default (no cap: Russian roulette ends paths), same seed and "
                     "spp, so both follow the same paths up to the cap and the difference is the truncation bias alone";
        s.reading = "A cap of N drops the light that arrives after more than N bounces: -a^(N+1) of the radiance in a "
                    "closed box of albedo a, a bias no number of samples removes. It saves the time of the long paths; "
                    "the default pays it so that the reference is unbiased.";
        sweeps.push_back(s);
    }
    return sweeps;
}

}  // namespace

Sizes sizes(bool quick) { return {quick ? 128 : 320, quick ? 96 : 240, quick ? 1 : 3, quick ? 3 : 10}; }
std::vector<int> light_counts(bool quick) { return quick ? std::vector<int>{4, 16} : std::vector<int>{4, 16, 64}; }
std::vector<int> spp_steps(bool quick) { return quick ? std::vector<int>{1, 4, 16} : std::vector<int>{1, 4, 16, 64}; }
std::vector<int> depth_steps(bool quick) { return quick ? std::vector<int>{2, 8} : std::vector<int>{2, 4, 8, 16, 32}; }

Plan make_plan(const Options& o) {
    Plan plan;
    plan.sweeps = make_sweeps(o.quick);
    if (!o.effects.empty()) {
        std::vector<AccuracySweep> kept;
        for (AccuracySweep& s : plan.sweeps)
            if (std::find(o.effects.begin(), o.effects.end(), s.effect) != o.effects.end()) kept.push_back(std::move(s));
        if (kept.empty()) throw bad_input("bench accuracy: no section named by --effect");
        plan.sweeps = std::move(kept);
    }
    std::vector<Features> features;  // of each given scene, loaded once
    for (const std::string& name : o.scenes) features.push_back(analyze(load_scene(o, name), RenderSettings{}));
    for (size_t i = 0; i < plan.sweeps.size(); ++i) {
        const AccuracySweep& s = plan.sweeps[i];
        if (s.effect == "forward_deferred" || s.effect == "ray_tracer" || s.effect == "ray_tracer_depth" || o.scenes.empty()) {
            plan.jobs.push_back({i, s.scene});
            continue;
        }
        for (size_t k = 0; k < o.scenes.size(); ++k)
            if (s.needed(features[k])) plan.jobs.push_back({i, o.scenes[k]});
    }
    return plan;
}

std::string section_scene(const AccuracySweep& s, const std::string& scene) {
    return s.effect == "forward_deferred" ? "generated:lights:N" : scene;
}

std::string job_label(const Plan& plan, const Job& j) {
    const AccuracySweep& s = plan.sweep(j);
    return s.effect + " on " + section_scene(s, j.scene);
}

int job_steps(const AccuracySweep& s, bool quick) {
    if (s.effect == "forward_deferred") return 2 * static_cast<int>(light_counts(quick).size());
    if (s.effect == "ray_tracer") return static_cast<int>(spp_steps(quick).size()) + 1;
    if (s.effect == "ray_tracer_depth") return static_cast<int>(depth_steps(quick).size()) + 1;
    return static_cast<int>(s.variants.size()) + 1 + (s.split ? 1 : 0);
}

Scene load_scene(const Options& o, const std::string& name) {
    if (name.rfind("generated:lights:", 0) == 0) return make_many_lights_scene(std::stoi(name.substr(17)));
    if (name == "generated:dof") return make_dof_scene();
    if (name == "generated:edges") return make_edges_scene();
    if (name == "generated:materials") return make_materials_scene();
    if (name == "generated:motion") return make_motion_scene();
    const fs::path p = fs::path(name).has_parent_path() ? fs::path(name) : o.scene_dir / name;
    return load_gltf(p);
}

}  // namespace candela::accuracy
