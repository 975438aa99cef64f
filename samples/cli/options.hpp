#pragma once
// What the `candela` subcommands share: the option parser, number and size parsing, and the
// scene set-up (scene file, lighting, render settings, GL context) of render, view and bench.
// Every function here throws candela::Error (bad_input, exit 2) with the message the user sees.
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "commands.hpp"
#include "platform/context.hpp"
#include "render/still.hpp"
#include "scene/lighting.hpp"
#include "scene/scene.hpp"

namespace candela::cli {

// The result of parse(): options of the form `--name VALUE` (or `--name=VALUE`) and flags;
// positional arguments are kept in order.
struct Parsed {
    std::vector<std::string> positional;
    std::map<std::string, std::vector<std::string>> values;  // every occurrence, in order
    std::map<std::string, bool> flags;
    bool has(const std::string& name) const { return values.count(name) > 0; }
    // The last occurrence: a repeated option overrides.
    const std::string& get(const std::string& name) const { return values.at(name).back(); }
    std::vector<std::string> all(const std::string& name) const {
        return has(name) ? values.at(name) : std::vector<std::string>{};
    }
};

// Splits args into the options listed in with_value, the flags listed in flags and positional
// arguments; any other argument starting with '-' is an unknown option.
Parsed parse(const Args& args, const std::vector<std::string>& with_value, const std::vector<std::string>& flags);

// Numbers given to `option`, accepted only if the whole text is a number in [lo, hi].
int parse_int(const std::string& option, const std::string& text, int lo, int hi);
float parse_float(const std::string& option, const std::string& text, float lo, float hi);
// `--size WxH`, each side in [1, 16384].
void parse_size(const std::string& text, int& w, int& h);
// `--backend auto|egl|osmesa` (auto_select when absent). quote_value puts the rejected value in
// the message (the scene set-up's wording); without it the message only lists the choices.
Backend backend_option(const Parsed& p, bool quote_value);
// `--shader-dir DIR`: an existing directory (a copy of shaders/ to edit or test), else the
// built-in shaders.
std::filesystem::path shader_dir_option(const Parsed& p);

// printf of one number into a string ("%.3g").
std::string format_number(const char* format, double v);

// A glTF file, or generated:N (a bumpy sphere of about N triangles) or generated:lights:N (N
// point lights over a floor with boxes). strict: loader warnings are errors.
Scene load_scene(const std::string& path, bool strict);
// Logs Scene::origin and why it is there.
void log_origin(const Scene& scene, const char* why);
// Moves Scene::origin to the camera (and poses the scene again) where the camera stands far from
// it compared with its near plane (scene/origin.hpp), and logs it.
void anchor_scene(Scene& scene, const std::string& camera, float aspect, int animation, float time);
// --lighting auto|file|default, then --environment FILE|none over what it chose (the rig's sky
// or the file's environment). The camera orients the rig's key light.
LightingChoice setup_lighting(Scene& scene, const Parsed& p, const std::string& camera, float aspect);

// The options that setup_scene() reads; a subcommand that uses it adds its own to these lists.
extern const std::vector<std::string> kSceneSetupOptions;
extern const std::vector<std::string> kSceneSetupFlags;

// The scene, settings and context choices shared by render, view and bench frame/reload.
struct SceneSetup {
    Scene scene;
    LightingChoice lighting;
    StillOptions options;
    Backend backend = Backend::auto_select;
    bool debug = false;  // --debug-gl or CANDELA_DEBUG_GL=1
    double load_ms = 0;
    std::filesystem::path shader_dir = ShaderLibrary::default_root();  // --shader-dir
    // --time T or A:B (seconds): the scene is posed at time_first (options.time) of
    // options.animation; render writes a sequence over [time_first, time_last].
    float time_first = 0.0f, time_last = 0.0f;
    int gl_errors_before = 0;  // GL errors counted before this set-up (a batch's earlier jobs)
};
// Reads kSceneSetupOptions/kSceneSetupFlags from p and loads scene_path; the image is
// default_w x default_h unless --size says otherwise.
SceneSetup setup_scene(const Parsed& p, const std::string& scene_path, int default_w, int default_h);

// Opens the GL context the set-up asks for; on failure prints why (the caller returns exit 3).
ContextResult open_context(const SceneSetup& s);
// With the context current: `--lighting auto` measures whether the file's own lights light the
// view and may add the default environment (rt/view_lighting.hpp). Before the scene is
// uploaded or traced.
void finish_lighting(SceneSetup& s, const ShaderLibrary& shaders);
// Says on stderr which of p's --set knobs belong to an effect the planner did not run (switched
// off, not called for by the scene, or waiting on another knob): such a knob changes nothing.
void warn_idle_knobs(const Parsed& p, const Features& features);
// Whether render makes texture mipmaps on a worker context (GlWorker): yes unless the
// environment sets CANDELA_MIP_WORKER=0 (a switch for comparing; the images are the same).
bool mip_worker_wanted();
// With --debug-gl: exit 1 if the GL debug output reported errors, else 0.
int check_gl_errors(const SceneSetup& s);

}  // namespace candela::cli
