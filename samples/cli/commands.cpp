#include "commands.hpp"

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>

#include <unistd.h>

#include "core/error.hpp"
#include "core/log.hpp"
#include "gl/debug.hpp"
#include "image/image.hpp"
#include "platform/context.hpp"
#include "profile/stats.hpp"
#include "render/still.hpp"
#include "rt/ray_rates.hpp"
#include "rt/ray_tracer.hpp"
#include <nlohmann/json.hpp>
#include "render/features.hpp"
#include "scene/features.hpp"
#include "scene/generate.hpp"
#include "scene/gltf_loader.hpp"
#include "scene/lighting.hpp"
#include "accuracy.hpp"
#include "shader/file_watcher.hpp"
#include "shader/program_catalog.hpp"
#include "viewer.hpp"

namespace candela::cli {
namespace fs = std::filesystem;

void print_usage() {
    std::fputs(
        "Candela: an OpenGL 4.5 renderer whose approximations are checked against its own ray tracer.\n"
        "\n"
        "usage:\n"
        "  candela render SCENE -o OUT.(png|exr) [--size WxH] [--backend auto|egl|osmesa]\n"
        "                 [--effects all|none|LIST] [--set KNOB=VALUE ...] [--camera N|NAME|auto]\n"
        "                 [--exposure EV] [--lighting auto|file|default] [--environment FILE|none]\n"
        "                 [--stats FILE.json] [--frames N] [--warmup N]\n"
        "                 [--debug-gl] [--verify-state] [--timings] [--strict] [--quiet]\n"
        "                 [--path auto|forward|deferred] [--output-buffer radiance|visibility]\n"
        "                 [--raytrace whitted|path|direct|indirect|ao|primary|visibility] [--spp N] [--max-depth N] [--seed N]\n"
        "                 [--spp-shard K/N] [--time-limit S] [--shader-dir DIR]\n"
        "  candela merge OUT.exr SHARD.exr...\n"
        "  candela info SCENE [--effects ...] [--set ...] [--lighting L] [--environment E] [--camera C] [--strict]\n"
        "  candela compare A B [--heatmap OUT.png] [--tolerance T] [--max-failing F] [--check] [--blocks K]\n"
        "  candela bench frame SCENE [--effects LIST ...] [--path P ...] [--size WxH] [--frames N] [--warmup N] [--json FILE]\n"
        "  candela bench rays SCENE|generated:N ... [--size WxH] [--spp N] [--repeat N]\n"
        "  candela bench reload SCENE [--size WxH] [--count N] [--shader-dir DIR]\n"
        "  candela bench accuracy [SCENE...] -o DIR [--report FILE.md] [--quick]\n"
        "  candela shaders check [--shader-dir DIR] [--backend auto|egl|osmesa]\n"
        "  candela view SCENE [--size WxH] [--effects ...] [--set ...] [--path P] [--camera C] [--shader-dir DIR]\n"
        "               [--script FILE] [--frames N] [--screenshot OUT.png] [--window-shot OUT.png] [--no-vsync]\n"
        "\n"
        "render   SCENE (.gltf/.glb) to OUT: .exr holds linear radiance; .png is exposure + ACES + sRGB.\n"
        "         --size WxH (default 512x512), --backend (default auto: EGL, then OSMesa),\n"
        "         --effects: all, none, or a comma list of shadows,ssao,rsm,transparency,reflections;\n"
        "         --set effect.knob=value (repeatable; 'candela info --knobs' lists them),\n"
        "         --camera glTF camera index or name (default: the first, else a framing camera;\n"
        "         auto: always the framing camera), --exposure EV for .png (default 0),\n"
        "         --lighting auto (default: the file's lights, or the default rig - a built-in sky and a\n"
        "         key light - when the file has none), file (the file's only) or default (the rig only),\n"
        "         --environment FILE (.hdr/.exr, equirectangular) replaces the environment, none removes\n"
        "         it, --stats writes executed passes with GPU/CPU ms and\n"
        "         counters, --frames N measured frames (median) after --warmup N, --debug-gl logs GL\n"
        "         debug output and fails on GL errors, --verify-state checks GL state between passes,\n"
        "         --timings prints where the time went, --strict treats loader warnings (missing\n"
        "         texture, skipped primitive, repaired data) as errors (exit 2).\n"
        "         --path forward|deferred (default auto: deferred from deferred.auto_lights lights),\n"
        "         --output-buffer visibility writes the fraction of light debug.light reaching each\n"
        "         pixel (shadow maps), to compare with --raytrace visibility (the exact answer).\n"
        "         --raytrace renders with the compute-shader ray tracer instead: --spp samples per\n"
        "         pixel (default 16), --max-depth bounces (whitted 5, path 8), --seed, --spp-shard K/N\n"
        "         computes the samples s with s %% N == K (alpha holds the sample count) and\n"
        "         --time-limit S stops at a sample boundary and still writes the image.\n"
        "         --shader-dir DIR reads the GLSL sources from DIR instead of the built-in shaders/.\n"
        "shaders  check: compiles every program and ray-tracer variant with glslang and links it\n"
        "         with the GL driver; exit 1 if any fails.\n"
        "view     the interactive viewer (a window: needs X; use xvfb-run or 'candela render' without\n"
        "         one); --size is the scene's size, the panel is docked beside it. Shaders under\n"
        "         --shader-dir reload when saved. --script FILE replays camera moves and setting\n"
        "         changes (samples/viewer/script.hpp), --frames N quits after N frames,\n"
        "         --screenshot writes the last frame's image, --window-shot the window with its panel.\n"
        "merge    the sample-weighted mean of --spp-shard outputs: equal to one run with all samples.\n"
        "info     counts, bounds, cameras, lights, the effects the scene calls for and the planned passes.\n"
        "compare  RMSE, relative MSE, PSNR, max difference and the pixels beyond --tolerance\n"
        "         (default 2/255) of A against B; --check exits 4 if more than --max-failing (default\n"
        "         0.001 = 0.1 %) of the pixels fail. --blocks K also compares A with a noisy reference B\n"
        "         as a viewer sees them: display values averaged over KxK blocks (mean and 99th\n"
        "         percentile of the difference) and the ratio of mean luminances.\n"
        "bench    rays: primary, AO and diffuse-bounce ray rates of the ray tracer (SCENE may be\n"
        "         generated:N triangles).\n"
        "         frame: median frame time and per-pass GPU time of each --effects variant (default\n"
        "         all and none) or, with several --path values, of each render path, measured\n"
        "         interleaved in one run (default 1280x720, 20 frames, 3 warm-up). SCENE may be\n"
        "         generated:lights:N (N point lights over a floor with boxes).\n"
        "         accuracy: every effect's knob sweep, timed and compared with the ray tracer's\n"
        "         reference: DIR/results.csv, report.md, plots and image strips (--quick: small, CI).\n"
        "         reload: median time from saving a shader file to the first frame drawn with the\n"
        "         rebuilt programs (a copy of the shaders is edited; default 1280x720, 10 saves).\n"
        "\n"
        "exit codes: 0 ok, 1 internal error, 2 bad input (file, option), 3 no usable OpenGL 4.5,\n"
        "            4 compare --check: images differ beyond the tolerance.\n",
        stdout);
}

namespace {

// Options of the form --name VALUE; positional arguments kept in order.
struct Parsed {
    std::vector<std::string> positional;
    std::map<std::string, std::vector<std::string>> values;  // every occurrence, in order
    std::map<std::string, bool> flags;
    bool has(const std::string& name) const { return values.count(name) > 0; }
    const std::string& get(const std::string& name) const { return values.at(name).back(); }
    std::vector<std::string> all(const std::string& name) const {
        return has(name) ? values.at(name) : std::vector<std::string>{};
    }
};

Parsed parse(const Args& args, const std::vector<std::string>& with_value, const std::vector<std::string>& flags) {
    Parsed p;
    for (size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        if (a.size() > 1 && a[0] == '-') {
            std::string name = a, value;
            bool has_inline = false;
            if (auto eq = a.find('='); eq != std::string::npos && a.rfind("--", 0) == 0) {
                name = a.substr(0, eq);
                value = a.substr(eq + 1);
                has_inline = true;
            }
            if (std::find(flags.begin(), flags.end(), name) != flags.end()) {
                p.flags[name] = true;
                continue;
            }
            if (std::find(with_value.begin(), with_value.end(), name) == with_value.end())
                throw bad_input("unknown option '" + name + "' (try 'candela --help')");
            if (!has_inline) {
                if (i + 1 >= args.size()) throw bad_input("option '" + name + "' needs a value");
                value = args[++i];
            }
            p.values[name].push_back(value);
        } else {
            p.positional.push_back(a);
        }
    }
    return p;
}

float parse_float(const std::string& option, const std::string& text, float lo, float hi) {
    try {
        size_t used = 0;
        const float v = std::stof(text, &used);
        if (used == text.size() && std::isfinite(v) && v >= lo && v <= hi) return v;
    } catch (const std::exception&) {
    }
    throw bad_input(option + " '" + text + "' is not a number in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
}

void parse_size(const std::string& text, int& w, int& h) {
    unsigned long a = 0, b = 0;
    char x = 0;
    char rest = 0;
    if (std::sscanf(text.c_str(), "%lu%c%lu%c", &a, &x, &b, &rest) != 3 || (x != 'x' && x != 'X') || a < 1 || b < 1 ||
        a > 16384 || b > 16384)
        throw bad_input("--size '" + text + "' must be WxH with 1 <= W, H <= 16384 (e.g. 512x512)");
    w = static_cast<int>(a);
    h = static_cast<int>(b);
}

std::string fmt(const char* f, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, f, v);
    return buf;
}

Scene load_scene(const std::string& path, bool strict) {
    if (path.rfind("generated:lights:", 0) == 0) {
        const std::string n = path.substr(17);
        if (n.empty() || n.size() > 6 || n.find_first_not_of("0123456789") != std::string::npos || std::stoul(n) < 1)
            throw bad_input(path + ": expected generated:lights:N with 1 <= N < 1e6 point lights");
        return make_many_lights_scene(static_cast<int>(std::stoul(n)));
    }
    if (path.rfind("generated:", 0) == 0) {
        const std::string n = path.substr(10);
        if (n.empty() || n.size() > 9 || n.find_first_not_of("0123456789") != std::string::npos || std::stoul(n) < 2)
            throw bad_input(path + ": expected generated:N with 2 <= N < 1e9 triangles");
        return make_bumpy_sphere_scene(std::stoul(n));
    }
    const int before = log::warning_count();
    Scene scene = load_gltf(path);
    const int warnings = log::warning_count() - before;
    if (strict && warnings > 0)
        throw bad_input(path + ": " + std::to_string(warnings) + " loader warning(s) (see above) and --strict is set");
    return scene;
}

// --lighting auto|file|default, then --environment FILE|none over what it chose (the rig's sky
// or the file's environment). The camera orients the rig's key light.
LightingChoice setup_lighting(Scene& scene, const Parsed& p, const std::string& camera, float aspect) {
    LightingMode mode = LightingMode::auto_select;
    if (p.has("--lighting")) {
        const auto m = parse_lighting_mode(p.get("--lighting"));
        if (!m) throw bad_input("--lighting '" + p.get("--lighting") + "' must be auto, file or default");
        mode = *m;
    }
    LightingChoice choice = apply_lighting(scene, mode, scene.select_camera(camera, aspect));
    if (p.has("--environment")) {
        const std::string env = p.get("--environment");
        if (env == "none") {
            scene.environment = Environment{};
            choice.reason += "; --environment none";
        } else {
            if (!fs::is_regular_file(env)) throw bad_input(env + ": --environment: no such file");
            scene.environment = Environment{};
            scene.environment.map = env;
            choice.reason += "; environment from --environment " + env;
        }
    }
    return choice;
}

// Options shared by render and bench frame: scene, context, settings.
struct SceneSetup {
    Scene scene;
    LightingChoice lighting;
    StillOptions options;
    Backend backend = Backend::auto_select;
    bool debug = false;
    double load_ms = 0;
    fs::path shader_dir = ShaderLibrary::default_root();  // --shader-dir
};

// --shader-dir DIR: an existing directory (a copy of shaders/ to edit or test).
fs::path shader_dir_option(const Parsed& p) {
    if (!p.has("--shader-dir")) return ShaderLibrary::default_root();
    const fs::path dir = p.get("--shader-dir");
    if (!fs::is_directory(dir)) throw bad_input("--shader-dir " + dir.string() + ": not a directory");
    return dir;
}

const std::vector<std::string> kSetupOptions = {"--size", "--backend", "--camera", "--environment", "--lighting", "--effects",
                                                "--set", "--frames", "--warmup", "--path", "--output-buffer",
                                                "--shader-dir"};
const std::vector<std::string> kSetupFlags = {"--debug-gl", "--strict", "--verify-state", "--quiet"};

int parse_int(const std::string& option, const std::string& text, int lo, int hi) {
    try {
        size_t used = 0;
        const long v = std::stol(text, &used);
        if (used == text.size() && v >= lo && v <= hi) return static_cast<int>(v);
    } catch (const std::exception&) {
    }
    throw bad_input(option + " '" + text + "' must be an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
}

SceneSetup setup_scene(const Parsed& p, const std::string& scene_path, int default_w, int default_h) {
    SceneSetup s;
    if (p.flags.count("--quiet")) log::set_level(log::Level::warn);
    s.options.width = default_w;
    s.options.height = default_h;
    if (p.has("--size")) parse_size(p.get("--size"), s.options.width, s.options.height);
    if (p.has("--camera")) s.options.camera = p.get("--camera");
    s.shader_dir = shader_dir_option(p);
    if (p.has("--frames")) s.options.frames = parse_int("--frames", p.get("--frames"), 1, 100000);
    if (p.has("--warmup")) s.options.warmup = parse_int("--warmup", p.get("--warmup"), 0, 100000);
    if (p.has("--effects")) apply_effects(s.options.settings, p.get("--effects"));
    if (p.has("--path")) {
        const std::string path = p.get("--path");
        if (path != "auto" && path != "forward" && path != "deferred")
            throw bad_input("--path '" + path + "' must be auto, forward or deferred");
        s.options.settings.path = path;
    }
    if (p.has("--output-buffer")) {
        const std::string b = p.get("--output-buffer");
        if (b != "radiance" && b != "visibility" && b != "ao" && b != "indirect")
            throw bad_input("--output-buffer '" + b + "' must be radiance, visibility (of light --set debug.light=K), ao or indirect");
        s.options.settings.debug.view = b == "radiance" ? "none" : b;
    }
    for (const std::string& knob : p.all("--set")) apply_knob(s.options.settings, knob);
    s.options.verify_state = p.flags.count("--verify-state") > 0;
    if (p.has("--backend")) {
        const auto b = parse_backend(p.get("--backend"));
        if (!b || *b == Backend::glfw) throw bad_input("--backend '" + p.get("--backend") + "' must be auto, egl or osmesa");
        s.backend = *b;
    }
    // CANDELA_DEBUG_GL=1 does the same as --debug-gl; the test suite sets it for every command.
    const char* debug_env = std::getenv("CANDELA_DEBUG_GL");
    s.debug = p.flags.count("--debug-gl") > 0 || (debug_env && std::string(debug_env) == "1");
    const auto t0 = std::chrono::steady_clock::now();
    s.scene = load_scene(scene_path, p.flags.count("--strict") > 0);
    s.lighting = setup_lighting(s.scene, p, s.options.camera,
                                static_cast<float>(s.options.width) / static_cast<float>(s.options.height));
    log::info("lighting: " + s.lighting.reason);
    s.load_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return s;
}

ContextResult open_context(const SceneSetup& s) {
    ContextOptions ctx_options;
    ctx_options.debug = s.debug;
    ContextResult ctx = create_context(s.backend, ctx_options);
    if (ctx.context && !ctx.notice.empty()) log::warn(ctx.notice);
    if (ctx.context) log::info(std::string("backend ") + to_string(ctx.context->backend()) + ": " + ctx.context->device_string());
    else std::fprintf(stderr, "candela: error: no usable OpenGL: %s\n", ctx.error.c_str());
    return ctx;
}

int check_gl_errors(const SceneSetup& s) {
    if (s.debug && gl::debug_error_count() > 0) {
        std::fprintf(stderr, "candela: error: %d GL error(s) (see above)\n", gl::debug_error_count());
        return static_cast<int>(ExitCode::internal);
    }
    return 0;
}

int raytrace(const Parsed& p, const SceneSetup& s, const fs::path& out_path, float exposure) {
    rt::Options o;
    const auto mode = rt::parse_mode(p.get("--raytrace"));
    if (!mode) throw bad_input("--raytrace '" + p.get("--raytrace") + "' must be whitted, path, direct, indirect, ao, primary or visibility");
    o.mode = *mode;
    if (p.has("--spp")) o.spp = parse_int("--spp", p.get("--spp"), 1, 1 << 24);
    if (p.has("--max-depth")) o.max_depth = parse_int("--max-depth", p.get("--max-depth"), 0, 64);
    if (p.has("--seed")) o.seed = static_cast<std::uint32_t>(parse_int("--seed", p.get("--seed"), 0, 2147483647));
    if (p.has("--time-limit")) o.time_limit_s = parse_float("--time-limit", p.get("--time-limit"), 0.0f, 1e9f);
    if (p.has("--spp-shard")) {
        int k = -1, n = -1;
        char rest = 0;
        if (std::sscanf(p.get("--spp-shard").c_str(), "%d/%d%c", &k, &n, &rest) != 2 || n < 1 || k < 0 || k >= n)
            throw bad_input("--spp-shard '" + p.get("--spp-shard") + "' must be K/N with 0 <= K < N");
        o.shard = k;
        o.shard_count = n;
    }
    o.ao_radius = s.options.settings.ao.radius;
    o.whitted_max_roughness = s.options.settings.rt.whitted_max_roughness;
    o.indirect_occlusion = s.options.settings.rt.indirect_occlusion;
    o.visibility_light = s.options.settings.debug.light;
    o.env_importance = s.options.settings.rt.env_importance;
    o.jitter = s.options.settings.rt.jitter == "auto" ? -1 : s.options.settings.rt.jitter == "on" ? 1 : 0;
    o.progress = true;
    const ShaderLibrary shaders(s.shader_dir);
    GpuScene gpu(s.scene);
    rt::RayTracer tracer(shaders, s.scene, gpu, o);
    const float aspect = static_cast<float>(s.options.width) / static_cast<float>(s.options.height);
    const rt::Result r = tracer.render(s.scene.select_camera(s.options.camera, aspect), s.options.width, s.options.height);
    const rt::BvhStats& b = tracer.scene().geometry().bvh.stats;
    log::info(std::string("ray traced '") + rt::to_string(o.mode) + "' [" + r.defines + "]: " + std::to_string(r.samples) +
              " spp in " + fmt("%.1f", r.trace_ms) + " ms; BVH " + std::to_string(b.node_count) + " nodes, depth " +
              std::to_string(b.max_depth) + ", SAH " + fmt("%.2f", b.sah_cost) + ", built in " + fmt("%.1f", b.build_ms) + " ms" +
              (r.stopped_early ? " (stopped by --time-limit)" : ""));
    if (r.nonfinite_samples) log::warn(std::to_string(r.nonfinite_samples) + " non-finite samples were replaced by 0");
    write_image(out_path, r.image, exposure);
    return check_gl_errors(s);
}

}  // namespace

int cmd_shaders(const Args& args) {
    const Parsed p = parse(args, {"--shader-dir", "--backend"}, {"--quiet"});
    if (p.positional.size() != 1 || p.positional[0] != "check") throw bad_input("usage: candela shaders check [--shader-dir DIR] [--backend B]");
    if (p.flags.count("--quiet")) log::set_level(log::Level::warn);
    SceneSetup s;
    s.shader_dir = shader_dir_option(p);
    if (p.has("--backend")) {
        const auto b = parse_backend(p.get("--backend"));
        if (!b || *b == Backend::glfw) throw bad_input("--backend must be auto, egl or osmesa");
        s.backend = *b;
    }
    const ShaderLibrary shaders(s.shader_dir);
    std::vector<ProgramDesc> programs = raster_programs();
    for (ProgramDesc& d : ray_tracer_variants()) programs.push_back(std::move(d));
    // glslang first: it needs no GL, so a machine without GL still checks the sources.
    int failed = 0;
    std::vector<bool> glslang_ok(programs.size(), true);
    for (size_t i = 0; i < programs.size(); ++i) {
        for (const auto& [stage, file] : programs[i].stages) {
            std::string problem;
            try {
                problem = validate_with_glslang(shaders.preprocess(file, programs[i].defines), stage);
            } catch (const Error& e) {
                problem = e.what();
            }
            if (!problem.empty()) {
                std::printf("FAIL glslang %s (%s):\n%s\n", programs[i].name.c_str(), file.string().c_str(), problem.c_str());
                glslang_ok[i] = false;
            }
        }
        failed += !glslang_ok[i];
    }
    ContextResult ctx = open_context(s);
    if (!ctx.context) {
        std::printf("%zu programs: %d failed glslang; no GL context for the driver check\n", programs.size(), failed);
        return static_cast<int>(failed ? ExitCode::internal : ExitCode::no_gl);
    }
    for (size_t i = 0; i < programs.size(); ++i) {
        const ShaderLibrary::BuildResult r = shaders.build(programs[i]);
        if (r.ok() && glslang_ok[i]) std::printf("ok   %s\n", programs[i].name.c_str());
        if (!r.ok()) {
            std::printf("FAIL driver %s:\n%s\n", programs[i].name.c_str(), r.log.c_str());
            failed += glslang_ok[i];
        }
    }
    std::printf("%zu programs (glslang and %s): %d failed\n", programs.size(), ctx.context->device_string().c_str(), failed);
    return failed ? static_cast<int>(ExitCode::internal) : 0;
}

int cmd_view(const Args& args) {
    std::vector<std::string> with_value = kSetupOptions;
    with_value.insert(with_value.end(), {"--script", "--screenshot", "--window-shot", "--exposure"});
    std::vector<std::string> flags = kSetupFlags;
    flags.push_back("--no-vsync");
    const Parsed p = parse(args, with_value, flags);
    if (p.positional.size() != 1) throw bad_input("view needs exactly one SCENE (got " + std::to_string(p.positional.size()) + ")");
    SceneSetup s = setup_scene(p, p.positional[0], 1280, 720);
    viewer::ViewerOptions o;
    o.width = s.options.width;
    o.height = s.options.height;
    o.settings = s.options.settings;
    o.camera = s.options.camera;
    o.lighting = s.lighting.reason;
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
    if (p.has("--exposure")) o.exposure_ev = parse_float("--exposure", p.get("--exposure"), -32, 32);
    return viewer::run_viewer(s.scene, o);
}

int cmd_merge(const Args& args) {
    const Parsed p = parse(args, {}, {});
    if (p.positional.size() < 2) throw bad_input("merge needs OUT.exr and at least one shard");
    std::vector<ImageF> shards;
    for (size_t i = 1; i < p.positional.size(); ++i) shards.push_back(read_image(p.positional[i]));
    write_image(p.positional[0], rt::merge_shards(shards));
    return 0;
}

int cmd_render(const Args& args) {
    std::vector<std::string> with_value = kSetupOptions;
    with_value.insert(with_value.end(), {"-o", "--output", "--exposure", "--stats", "--raytrace", "--spp", "--max-depth",
                                         "--seed", "--spp-shard", "--time-limit"});
    std::vector<std::string> flags = kSetupFlags;
    flags.push_back("--timings");
    const Parsed p = parse(args, with_value, flags);
    if (p.positional.size() != 1) throw bad_input("render needs exactly one SCENE (got " + std::to_string(p.positional.size()) + ")");
    std::string out = p.has("-o") ? p.get("-o") : p.has("--output") ? p.get("--output") : "";
    if (out.empty()) throw bad_input("render needs -o OUT.png or -o OUT.exr");
    const fs::path out_path(out);
    {
        std::string e = out_path.extension().string();
        for (auto& c : e) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
        if (e != ".png" && e != ".exr") throw bad_input(out + ": the output must be .png or .exr");
    }
    const float exposure = p.has("--exposure") ? parse_float("--exposure", p.get("--exposure"), -32, 32) : 0.0f;
    // Fail before rendering, not after: the output's directory must exist.
    {
        const fs::path dir = out_path.has_parent_path() ? out_path.parent_path() : fs::path(".");
        if (!fs::is_directory(dir)) throw bad_input(out + ": cannot write: no directory " + dir.string());
        if (access(dir.c_str(), W_OK) != 0) throw bad_input(out + ": cannot write: " + dir.string() + " is not writable");
    }
    SceneSetup s = setup_scene(p, p.positional[0], 512, 512);
    // A .png gets its display transform on the GPU (the tonemap pass); an .exr is the HDR target.
    const bool display = is_display_format(out_path);
    s.options.output = display ? FrameOutput::display : FrameOutput::hdr;
    s.options.exposure_ev = exposure;

    auto t0 = std::chrono::steady_clock::now();
    ContextResult ctx = open_context(s);
    if (!ctx.context) return static_cast<int>(ExitCode::no_gl);
    const double context_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();

    const ShaderLibrary shaders(s.shader_dir);
    if (p.has("--raytrace")) return raytrace(p, s, out_path, exposure);
    const StillResult result = render_still(s.scene, shaders, s.options);
    const std::size_t bad = count_nonfinite(result.radiance);
    if (bad) log::warn(out + ": " + std::to_string(bad) + " non-finite values in the rendered radiance (written as 0 in .png)");
    t0 = std::chrono::steady_clock::now();
    if (display) write_display_rgba8(out_path, result.display, result.radiance.width, result.radiance.height);
    else write_image(out_path, result.radiance, exposure);
    const double write_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    if (p.has("--stats")) {
        nlohmann::json j = stats_json({ctx.context->device_string(), to_string(ctx.context->backend()), p.positional[0]},
                                      s.options, result);
        j["setup_ms"]["load"] = s.load_ms;
        j["setup_ms"]["context"] = context_ms;
        j["setup_ms"]["write"] = write_ms;
        write_json(p.get("--stats"), j);
    }
    if (p.flags.count("--timings"))
        std::fprintf(stderr,
                     "candela: timings (ms): load %.1f, context %.1f, upload %.1f, shaders %.1f, frame %.1f (median of %d), "
                     "readback %.1f, write %.1f; %zu passes\n",
                     s.load_ms, context_ms, result.upload_ms, result.shader_ms, result.median_frame_ms(), s.options.frames,
                     result.readback_ms, write_ms, result.report.passes.size());
    return check_gl_errors(s);
}

// `candela bench rays SCENE...`: ray rates of the compute-shader tracer. SCENE may be a glTF
// file or generated:N (a bumpy sphere of about N triangles).
int bench_rays(const Args& args) {
    const Parsed p = parse(args, {"--size", "--spp", "--backend", "--repeat"}, {"--quiet"});
    if (p.positional.empty()) throw bad_input("bench rays needs at least one SCENE (a .gltf or generated:N)");
    if (p.flags.count("--quiet")) log::set_level(log::Level::warn);
    int w = 512, h = 512;
    if (p.has("--size")) parse_size(p.get("--size"), w, h);
    const int spp = p.has("--spp") ? parse_int("--spp", p.get("--spp"), 1, 4096) : 8;
    const int repeats = p.has("--repeat") ? parse_int("--repeat", p.get("--repeat"), 1, 100) : 3;
    SceneSetup s;
    if (p.has("--backend")) {
        const auto b = parse_backend(p.get("--backend"));
        if (!b || *b == Backend::glfw) throw bad_input("--backend must be auto, egl or osmesa");
        s.backend = *b;
    }
    ContextResult ctx = open_context(s);
    if (!ctx.context) return static_cast<int>(ExitCode::no_gl);
    const ShaderLibrary shaders(s.shader_dir);
    std::printf("device: %s (%s); %dx%d, %d spp per mode, medians of %d runs after one warm-up sample\n",
                ctx.context->device_string().c_str(), to_string(ctx.context->backend()), w, h, spp, repeats);
    std::printf("%-28s %10s %10s %10s %12s %12s %12s %10s %10s\n", "scene", "triangles", "bvh ms", "SAH", "primary Mr/s",
                "AO Mr/s", "bounce Mr/s", "nodes/ray", "prims/ray");
    for (const std::string& name : p.positional) {
        const Scene scene = load_scene(name, false);
        GpuScene gpu(scene);
        const Camera camera = scene.select_camera("", static_cast<float>(w) / static_cast<float>(h));
        const rt::RayRates r = rt::measure_ray_rates(shaders, scene, gpu, camera, w, h, spp, repeats);
        std::printf("%-28s %10zu %10.1f %10.2f %12.2f %12.2f %12.2f %10.1f %10.1f\n",
                    name.substr(name.size() > 28 ? name.size() - 28 : 0).c_str(), r.triangles, r.bvh.build_ms, r.bvh.sah_cost,
                    r.primary_mrays, r.ao_mrays, r.bounce_mrays, r.nodes_per_ray, r.primitives_per_ray);
    }
    return 0;
}

// The time from a shader file's save to the first frame drawn with the rebuilt program: a copy
// of the shaders is edited (a comment appended to lighting/shading.glsl, which the shading
// programs include) and the watcher, the reload and one frame run as in the viewer.
int bench_reload(const Args& args) {
    std::vector<std::string> with_value = kSetupOptions;
    with_value.push_back("--count");
    const Parsed p = parse(args, with_value, kSetupFlags);
    if (p.positional.size() != 1) throw bad_input("bench reload needs exactly one SCENE");
    SceneSetup s = setup_scene(p, p.positional[0], 1280, 720);
    const int count = p.has("--count") ? parse_int("--count", p.get("--count"), 1, 1000) : 10;
    ContextResult ctx = open_context(s);
    if (!ctx.context) return static_cast<int>(ExitCode::no_gl);
    const fs::path dir = fs::temp_directory_path() / ("candela_reload_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::copy(s.shader_dir, dir, fs::copy_options::recursive);
    struct Cleanup {
        fs::path dir;
        ~Cleanup() {
            std::error_code ec;
            fs::remove_all(dir, ec);
        }
    } cleanup{dir};
    const ShaderLibrary shaders(dir);
    GpuScene gpu(s.scene);
    Renderer renderer(shaders, s.scene, gpu, s.options.settings);
    const Camera camera = s.scene.select_camera(s.options.camera, static_cast<float>(s.options.width) / static_cast<float>(s.options.height));
    FileWatcher watcher(dir);
    for (int i = 0; i < 2; ++i) renderer.render(camera, s.options.width, s.options.height, FrameOutput::display);
    glFinish();
    const fs::path file = dir / "lighting" / "shading.glsl";
    std::vector<double> total, rebuild, frame;
    for (int i = 0; i < count; ++i) {
        { std::ofstream(file, std::ios::app) << "// edit " << i << "\n"; }
        const auto t0 = std::chrono::steady_clock::now();
        std::vector<fs::path> changed;
        while ((changed = watcher.poll()).empty())
            if (std::chrono::steady_clock::now() - t0 > std::chrono::seconds(10)) throw Error(ExitCode::internal, "bench reload: the watcher saw no change in 10 s");
        const ShaderReload r = renderer.reload_shaders(changed);
        if (!r.errors.empty()) throw Error(ExitCode::internal, r.errors[0]);
        const auto t1 = std::chrono::steady_clock::now();
        renderer.render(camera, s.options.width, s.options.height, FrameOutput::display);
        glFinish();
        const auto t2 = std::chrono::steady_clock::now();
        rebuild.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
        frame.push_back(std::chrono::duration<double, std::milli>(t2 - t1).count());
        total.push_back(std::chrono::duration<double, std::milli>(t2 - t0).count());
    }
    std::printf("device: %s (%s), %s at %dx%d, %d saves of lighting/shading.glsl (watcher: %s)\n", ctx.context->device_string().c_str(),
                to_string(ctx.context->backend()), p.positional[0].c_str(), s.options.width, s.options.height, count,
                watcher.uses_inotify() ? "inotify" : "polling");
    std::printf("save -> new frame: median %.1f ms (notice + rebuild %.1f ms, first frame with the new program %.1f ms)\n",
                median(total), median(rebuild), median(frame));
    return check_gl_errors(s);
}

int cmd_bench(const Args& args) {
    if (!args.empty() && args[0] == "rays") return bench_rays(Args(args.begin() + 1, args.end()));
    if (!args.empty() && args[0] == "reload") return bench_reload(Args(args.begin() + 1, args.end()));
    if (!args.empty() && args[0] == "accuracy") {
        const Parsed p = parse(Args(args.begin() + 1, args.end()), {"-o", "--report", "--shader-dir", "--backend"}, {"--quick", "--quiet"});
        if (!p.has("-o")) throw bad_input("bench accuracy needs -o DIR");
        if (p.flags.count("--quiet")) log::set_level(log::Level::warn);
        AccuracyOptions o;
        o.scenes = p.positional;
        for (const std::string& s : o.scenes)
            if (!fs::is_regular_file(s)) throw bad_input(s + ": no such file");
        o.out = p.get("-o");
        if (p.has("--report")) o.report = p.get("--report");
        o.quick = p.flags.count("--quick") > 0;
        o.shader_dir = shader_dir_option(p);
        // The sample scenes sit beside the built-in shaders in the source tree.
        o.scene_dir = fs::path(ShaderLibrary::default_root()).parent_path() / "samples" / "scenes";
        if (p.has("--backend")) {
            const auto b = parse_backend(p.get("--backend"));
            if (!b || *b == Backend::glfw) throw bad_input("--backend must be auto, egl or osmesa");
            o.backend = *b;
        }
        o.command_line = "candela bench accuracy";
        for (size_t i = 1; i < args.size(); ++i) o.command_line += " " + (args[i].find('/') != std::string::npos && fs::path(args[i]).is_absolute() ? fs::path(args[i]).filename().string() : args[i]);
        return run_accuracy(o);
    }
    if (args.empty() || args[0] != "frame")
        throw bad_input("bench needs a benchmark: 'candela bench frame SCENE' or 'candela bench rays SCENE...'");
    const Args rest(args.begin() + 1, args.end());
    std::vector<std::string> with_value = kSetupOptions;
    with_value.push_back("--json");
    const Parsed p = parse(rest, with_value, kSetupFlags);
    if (p.positional.size() != 1) throw bad_input("bench frame needs exactly one SCENE");
    SceneSetup s = setup_scene(p, p.positional[0], 1280, 720);
    if (!p.has("--frames")) s.options.frames = 20;
    if (!p.has("--warmup")) s.options.warmup = 3;
    s.options.output = FrameOutput::display;  // what a viewer's frame includes
    // Each --effects value is one variant; the variants are measured interleaved, frame by frame,
    // so that they see the same machine conditions.
    std::vector<std::string> variants = p.all("--effects");
    const std::vector<std::string> paths = p.all("--path");
    const bool path_variants = paths.size() >= 2;
    if (path_variants && variants.size() > 1) throw bad_input("bench frame: several --path values take at most one --effects");
    if (path_variants) {
        const std::string effects = variants.empty() ? "all" : variants[0];
        variants.clear();
        for (const auto& path : paths) variants.push_back(effects + " --path " + path);
    }
    if (variants.empty()) variants = {"all", "none"};
    ContextResult ctx = open_context(s);
    if (!ctx.context) return static_cast<int>(ExitCode::no_gl);
    const ShaderLibrary shaders(s.shader_dir);
    std::vector<StillOptions> options(variants.size(), s.options);
    std::vector<std::unique_ptr<FrameLoop>> loops;
    for (size_t v = 0; v < variants.size(); ++v) {
        const size_t space = variants[v].find(" --path ");
        apply_effects(options[v].settings, variants[v].substr(0, space));
        if (space != std::string::npos) apply_knob(options[v].settings, "render.path=" + variants[v].substr(space + 8));
        for (const std::string& knob : p.all("--set")) apply_knob(options[v].settings, knob);
        loops.push_back(std::make_unique<FrameLoop>(s.scene, shaders, options[v]));
    }
    for (auto& loop : loops) loop->warmup(s.options.warmup);
    for (int f = 0; f < s.options.frames; ++f)
        for (auto& loop : loops) loop->measure_frame();
    std::vector<StillResult> results;
    for (auto& loop : loops) results.push_back(loop->finish());
    std::printf("device: %s (%s)\nscene: %s at %dx%d, %d frames per variant after %d warm-up\n",
                ctx.context->device_string().c_str(), to_string(ctx.context->backend()), p.positional[0].c_str(),
                s.options.width, s.options.height, s.options.frames, s.options.warmup);
    nlohmann::json all = nlohmann::json::array();
    for (size_t v = 0; v < variants.size(); ++v) {
        const auto [q1, q3] = quartiles(results[v].frame_ms);
        std::printf("effects=%-12s frame median %8.2f ms  IQR [%.2f, %.2f]  graph %.3f ms  passes:", variants[v].c_str(),
                    results[v].median_frame_ms(), q1, q3, results[v].report.graph_ms);
        for (const auto& ps : results[v].report.passes) std::printf(" %s %.2f", ps.name.c_str(), ps.gpu_ms);
        std::printf(" (GPU ms, median)\n");
        all.push_back(stats_json({ctx.context->device_string(), to_string(ctx.context->backend()), p.positional[0]},
                                 options[v], results[v]));
    }
    if (variants.size() >= 2)
        std::printf("ratio %s / %s = %.3f\n", variants[0].c_str(), variants[1].c_str(),
                    results[0].median_frame_ms() / results[1].median_frame_ms());
    if (p.has("--json")) write_json(p.get("--json"), all);
    return check_gl_errors(s);
}

int cmd_info(const Args& args) {
    const Parsed p = parse(args, {"--effects", "--set", "--path", "--lighting", "--environment", "--camera"}, {"--strict", "--knobs"});
    if (p.flags.count("--knobs")) {
        for (const KnobInfo& k : knob_infos())
            std::printf("%-28s %-6s %-22s %s\n", k.name.c_str(), k.type.c_str(), k.range.c_str(), k.help.c_str());
        return 0;
    }
    if (p.positional.size() != 1) throw bad_input("info needs exactly one SCENE");
    RenderSettings settings;
    if (p.has("--effects")) apply_effects(settings, p.get("--effects"));
    if (p.has("--path")) apply_knob(settings, "render.path=" + p.get("--path"));
    for (const std::string& knob : p.all("--set")) apply_knob(settings, knob);
    Scene scene = load_scene(p.positional[0], p.flags.count("--strict") > 0);
    const std::string camera_choice = p.has("--camera") ? p.get("--camera") : "";
    const LightingChoice lighting = setup_lighting(scene, p, camera_choice, 1.0f);
    int directional = 0, point = 0, spot = 0;
    for (const auto& pl : scene.placed_lights()) {
        directional += pl.light->type == LightType::directional;
        point += pl.light->type == LightType::point;
        spot += pl.light->type == LightType::spot;
    }
    int valid_images = 0;
    for (const Image& img : scene.images) valid_images += img.valid && img.name != "fallback";
    const Bounds b = scene.world_bounds();
    std::printf("scene: %s\n", scene.source.string().c_str());
    std::printf("nodes: %zu  meshes: %zu  triangles: %zu  materials: %zu  textures: %d (%d missing)\n",
                scene.nodes.size(), scene.meshes.size(), scene.triangle_count(), scene.materials.size(), valid_images,
                scene.sanitized.missing_textures);
    std::printf("lights: %d directional, %d point, %d spot\n", directional, point, spot);
    if (!scene.ignored.empty()) {
        std::string list;
        for (const std::string& what : scene.ignored) list += (list.empty() ? "" : "; ") + what;
        std::printf("ignored (not implemented): %s\n", list.c_str());
    }
    if (b.empty()) std::printf("bounds: empty\n");
    else
        std::printf("bounds: min (%.4g, %.4g, %.4g)  max (%.4g, %.4g, %.4g)\n", b.min.x, b.min.y, b.min.z, b.max.x,
                    b.max.y, b.max.z);
    std::printf("cameras: %zu\n", scene.cameras.size());
    for (size_t i = 0; i < scene.cameras.size(); ++i) {
        const Camera& c = scene.cameras[i];
        const glm::vec3 pos(c.world[3]);
        std::printf("  [%zu] '%s' %s at (%.3g, %.3g, %.3g)\n", i, c.name.c_str(),
                    c.orthographic ? "orthographic" : (std::string("perspective yfov ") + fmt("%.3g", c.yfov)).c_str(),
                    pos.x, pos.y, pos.z);
    }
    {
        const Camera auto_cam = framing_camera(b);
        const glm::vec3 pos(auto_cam.world[3]);
        std::printf("  [auto] framing camera from the bounds, perspective yfov %.3g at (%.3g, %.3g, %.3g)%s\n", auto_cam.yfov,
                    pos.x, pos.y, pos.z, scene.cameras.empty() ? " (the default: the file has no camera)" : "");
    }
    std::printf("lighting: %s\n", lighting.reason.c_str());
    std::printf("environment: %s\n", scene.environment.image ? scene.environment.label.c_str()
                                     : !scene.environment.map.empty() ? scene.environment.map.string().c_str()
                                     : scene.environment.present()
                                         ? ("constant (" + fmt("%.3g", scene.environment.radiance.r) + ", " +
                                            fmt("%.3g", scene.environment.radiance.g) + ", " +
                                            fmt("%.3g", scene.environment.radiance.b) + ")").c_str()
                                         : "none");
    const Features features = analyze(scene, settings);
    std::printf("scene features:\n");
    for (const Feature* feat : features.scene.all())
        std::printf("  %-22s %-4s %s\n", (feat->name + ":").c_str(), feat->needed ? "yes" : "no", feat->reason.c_str());
    std::printf("effects:\n");
    for (const EffectDecision* d : features.effects())
        std::printf("  %-22s %s\n", (d->name + ":").c_str(), d->reason.c_str());
    std::printf("planned passes:\n");
    for (const PlannedPass& pass : plan_passes(features, settings))
        std::printf("  %-22s %s\n", pass.name.c_str(), pass.why.c_str());
    return 0;
}

int cmd_compare(const Args& args) {
    const Parsed p = parse(args, {"--heatmap", "--tolerance", "--max-failing", "--blocks"}, {"--check"});
    if (p.positional.size() != 2) throw bad_input("compare needs two images A B");
    const double tolerance = p.has("--tolerance") ? parse_float("--tolerance", p.get("--tolerance"), 0, 1e30f) : 2.0 / 255.0;
    const double max_failing = p.has("--max-failing") ? parse_float("--max-failing", p.get("--max-failing"), 0, 1) : 0.001;
    const ImageF a = read_image(p.positional[0]);
    const ImageF b = read_image(p.positional[1]);
    if (a.width != b.width || a.height != b.height)
        throw bad_input(p.positional[0] + " is " + std::to_string(a.width) + "x" + std::to_string(a.height) + " but " +
                        p.positional[1] + " is " + std::to_string(b.width) + "x" + std::to_string(b.height));
    const CompareResult r = compare(a, b, tolerance);
    std::printf("rmse %.6g\nrelative_mse %.6g\npsnr %.3f dB\nmax_abs %.6g\nfailing_pixels %zu (%.4f %%, tolerance %.6g)\nnonfinite %zu\n",
                r.rmse, r.relative_mse, r.psnr, r.max_abs, r.failing_pixels, 100.0 * r.failing_fraction, tolerance,
                r.nonfinite);
    if (p.has("--blocks")) {
        const BlockAgreement g = block_agreement(a, b, parse_int("--blocks", p.get("--blocks"), 1, 4096));
        std::printf("block_mean_abs_display %.6g\nblock_p99_abs_display %.6g\nmean_luminance_ratio %.6g\n", g.mean_abs,
                    g.p99_abs, g.luminance_ratio);
    }
    if (p.has("--heatmap")) write_display_image(p.get("--heatmap"), heatmap(a, b, std::max(tolerance * 4, 1e-6)));
    if (p.flags.count("--check") && (r.failing_fraction > max_failing || r.nonfinite > 0)) return 4;
    return 0;
}

}  // namespace candela::cli
