#pragma once
// `candela view SCENE`: the interactive viewer. A GLFW window shows the raster frame; a Dear
// ImGui panel docked to its right edge (the scene is drawn only left of it; H hides it) holds the render path, every effect and knob of RenderSettings (the names of
// --set), the planned and culled passes with their reasons, per-pass GPU times and counters,
// and shader errors. Shaders under --shader-dir reload when saved. Effects that converge over
// frames (GI probes: gi.budget rays per frame, their interactive default unless --set gives it)
// do so and the panel says how far.
// Animated scenes play their first animation, looping; the panel's Animation section
// chooses the animation, plays, pauses, scrubs and sets the speed (viewer/playback.hpp).
#include <filesystem>
#include <string>
#include <vector>

#include "accuracy/error_budget.hpp"
#include "render/settings.hpp"
#include "scene/lighting.hpp"
#include "scene/scene.hpp"

namespace candela::viewer {

struct ViewerOptions {
    int width = 1280, height = 720;    // the scene's size; the window is wider by the panel
    RenderSettings settings;
    std::vector<std::string> set_knobs; // the --set assignments as given: the viewer's defaults (gi.budget) leave these alone
    std::string camera;                // scene camera to start with ("" = the first)
    std::filesystem::path shader_dir;  // watched and reloaded
    std::filesystem::path script;      // --script FILE (viewer/script.hpp)
    std::filesystem::path screenshot;  // --screenshot OUT.png: the scene's image (no UI) after the last frame
    std::filesystem::path window_shot; // --window-shot OUT.png: the whole window with the panel
    int frames = 0;                    // --frames N: quit after N frames (0: when closed)
    bool vsync = true;
    float exposure_ev = 0.0f;
    // Which lighting the scene got and why (scene/lighting.hpp), shown in the panel; the viewer
    // completes it with its context (rt/view_lighting.hpp) before uploading the scene.
    LightingChoice lighting;
    // --animation N|NAME|none: the animation to play ("": the first, if the scene has any; none:
    // the rest pose). --time T: start paused at T seconds (the pose `render --time T` draws);
    // < 0: start at 0, playing.
    std::string animation;
    float time = -1.0f;
    // --error-budget E [--budget-model FILE] (viewer/budget_mode.hpp): the budget is on from the
    // first frame (0: off until the panel or a script turns it on); the model the panel and the
    // script's `budget` choose with.
    double error_budget = 0.0;
    budget::Model budget_model = budget::builtin_model();
    std::string budget_model_label = "built-in";
};

// Runs until the window closes, the script quits or --frames have passed. Returns the exit code:
// 0, or 3 when no window with OpenGL 4.5 can be opened (the message says why and what to use).
// The viewer poses `scene` (animation.hpp pose_scene) as the animation plays.
int run_viewer(Scene& scene, const ViewerOptions& options);

}  // namespace candela::viewer
