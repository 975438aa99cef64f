// `candela view`: the interactive viewer (samples/viewer).
#include "commands.hpp"

#include <string>
#include <vector>

#include "budget.hpp"
#include "core/error.hpp"
#include "options.hpp"
#include "viewer.hpp"

namespace candela::cli {
namespace fs = std::filesystem;

int cmd_view(const Args& args) {
    std::vector<std::string> with_value = kSceneSetupOptions;
    with_value.insert(with_value.end(), {"--script", "--screenshot", "--window-shot", "--exposure"});
    with_value.insert(with_value.end(), kBudgetOptions.begin(), kBudgetOptions.end());
    std::vector<std::string> flags = kSceneSetupFlags;
    flags.push_back("--no-vsync");
    const Parsed p = parse(args, with_value, flags);
    if (p.positional.size() != 1) throw bad_input("view needs exactly one SCENE (got " + std::to_string(p.positional.size()) + ")");
    // --error-budget E [--budget-model FILE]: bad input is found before the scene loads.
    const std::optional<BudgetRequest> budget_req = budget_request(p);
    SceneSetup s = setup_scene(p, p.positional[0], 1280, 720);
    viewer::ViewerOptions o;
    o.width = s.options.width;
    o.height = s.options.height;
    o.settings = s.options.settings;
    o.set_knobs = p.all("--set");  // the viewer's defaults (gi.budget) leave the user's knobs alone
    o.camera = s.options.camera;
    o.lighting = s.lighting;
    o.shader_dir = s.shader_dir;
    o.frames = p.has("--frames") ? s.options.frames : 0;
    o.vsync = !p.flags.count("--no-vsync");
    if (p.has("--script")) {
        o.script = p.get("--script");
        if (!fs::is_regular_file(o.script)) throw bad_input(o.script.string() + ": --script: no such file");
    }
    if (p.has("--screenshot")) o.screenshot = p.get("--screenshot");
    if (p.has("--window-shot")) o.window_shot = p.get("--window-shot");
    for (const fs::path& out : {o.screenshot, o.window_shot})
        if (!out.empty() && out.extension() != ".png") throw bad_input(out.string() + ": screenshots are .png");
    if ((!o.screenshot.empty() || !o.window_shot.empty()) && o.frames == 0 && o.script.empty())
        throw bad_input("--screenshot/--window-shot need --frames N (the frame to capture)");
    if (p.has("--animation")) o.animation = p.get("--animation");
    if (p.has("--time")) {  // one time: the viewer starts paused there
        if (p.get("--time").find(':') != std::string::npos) throw bad_input("--time A:B (a sequence) is for render; view takes one time T");
        o.time = parse_float("--time", p.get("--time"), 0.0f, 1e6f);
    }
    if (p.has("--exposure")) o.exposure_ev = parse_float("--exposure", p.get("--exposure"), -32, 32);
    if (budget_req) {
        o.error_budget = budget_req->budget;
        o.budget_model = budget_req->model;
        o.budget_model_label = budget_req->model_label;
    }
    return viewer::run_viewer(s.scene, o);
}

}  // namespace candela::cli
