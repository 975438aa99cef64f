#include "options.hpp"

#include "scene/animation.hpp"
#include "scene/origin.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "core/error.hpp"
#include "core/log.hpp"
#include "gl/debug.hpp"
#include "render/effect_registry.hpp"
#include "render/features.hpp"
#include "render/settings.hpp"
#include "rt/view_lighting.hpp"
#include "scene/generate.hpp"
#include "scene/gltf_loader.hpp"

namespace candela::cli {
namespace fs = std::filesystem;

namespace {
std::string usage_text() {
    // The effect names come from the engine's registry: the CLI names no effect.
    std::string effect_list;
    for (const std::string& name : effect_names()) effect_list += (effect_list.empty() ? "" : ",") + name;
    const std::string text =
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
        "                 [--spp-shard K/N] [--time-limit S] [--shader-dir DIR] [--variant NAME|INDEX|default]\n"
        "  candela batch JOBS.json|JOBS.txt [--backend auto|egl|osmesa] [--debug-gl] [--timings] [--quiet]\n"
        "  candela merge OUT.exr SHARD.exr...\n"
        "  candela farm reference SCENE -o DIR --shards N [render's options] [--batch-stats]\n"
        "  candela farm sweep [SCENE...] -o DIR [bench accuracy's options]\n"
        "               (both: [--sbatch ARG]... [--dry-run] [--submit [--wait]])\n"
        "  candela farm task|finish|status|submit DIR [INDEX] [--wait]\n"
        "  candela info SCENE [--effects ...] [--set ...] [--lighting L] [--environment E] [--camera C] [--size WxH] [--variant V]\n"
        "              [--strict]\n"
        "  candela compare A B [--heatmap OUT.png] [--tolerance T] [--max-failing F] [--check] [--blocks K]\n"
        "  candela compare --batches A1.exr A2.exr... --against B1.exr B2.exr...|REF.exr [--ref-stderr SE.exr]\n"
        "                  [--z-threshold Z] [--z-map OUT.png] [--save-mean M.exr] [--save-stderr S.exr]\n"
        "  candela bench frame SCENE [--effects LIST ...] [--path P ...] [--size WxH] [--frames N] [--warmup N] [--json FILE]\n"
        "                    [--variant V]\n"
        "  candela bench rays SCENE|generated:N ... [--size WxH] [--spp N] [--repeat N]\n"
        "  candela bench reload SCENE [--size WxH] [--count N] [--shader-dir DIR]\n"
        "  candela bench lights [--scene bounded|street|emitters] [--counts N,N,...] [--size WxH] [--spp N] [--set KNOB=VALUE ...]\n"
        "  candela bench accuracy [SCENE...] -o DIR [--report FILE.md] [--quick] [--effect NAME...]\n"
        "  candela bench error-budget SCENE... --csv OUT.csv [--size WxH] [--spp N] [--frames N]\n"
        "  candela bench error-budget --fit CSV... -o MODEL.json|MODEL.inc | --evaluate CSV... [--budgets E,...]\n"
        "  candela render|info|view|bench frame SCENE ... --error-budget E [--budget-model FILE.json] (render: [--verify [--spp N]])\n"
        "  candela shaders check [--shader-dir DIR] [--backend auto|egl|osmesa]\n"
        "  candela view SCENE [--size WxH] [--effects ...] [--set ...] [--path P] [--camera C] [--shader-dir DIR]\n"
        "               [--script FILE] [--frames N] [--screenshot OUT.png] [--window-shot OUT.png] [--no-vsync]\n"
        "  candela --version [--backend auto|egl|osmesa]\n"
        "\n"
        "render   SCENE (.gltf/.glb) to OUT: .exr holds linear radiance; .png is exposure + ACES + sRGB.\n"
        "         --size WxH (default 512x512), --backend (default auto: EGL, then OSMesa),\n"
        "         --effects: all, none, or a comma list of " + effect_list + ";\n"
        "         --set effect.knob=value (repeatable; 'candela info --knobs' lists them),\n"
        "         --camera glTF camera index or name (default: the first, else a framing camera;\n"
        "         auto: always the framing camera), --exposure EV for .png (default 0),\n"
        "         --variant the KHR_materials_variants variant by name or index (default: the file's\n"
        "         own materials; 'candela info' lists them; an unknown one is bad input, exit 2;\n"
        "         also for info, view, bench frame and batch jobs),\n"
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
        "         pixel (default 16), --max-depth bounces (whitted 5; path: no cap, Russian\n"
        "         roulette ends paths; a set N drops light after N bounces, a bias), --seed,\n"
        "         --spp-shard K/N computes the samples s with s % N == K (alpha holds the\n"
        "         sample count; `compare --batches` tests such batches statistically) and\n"
        "         --time-limit S stops at a sample boundary and still writes the image.\n"
        "         --shader-dir DIR reads the GLSL sources from DIR instead of the built-in shaders/.\n"
        "shaders  check: compiles every program and ray-tracer variant with glslang and links it\n"
        "         with the GL driver; exit 1 if any fails.\n"
        "view     the interactive viewer (a window: needs X; use xvfb-run or 'candela render' without\n"
        "         one); --size is the scene's size, the panel is docked beside it. Shaders under\n"
        "         --shader-dir reload when saved. --script FILE replays camera moves and setting\n"
        "         changes (samples/viewer/script.hpp), --frames N quits after N frames,\n"
        "         --screenshot writes the last frame's image, --window-shot the window with its panel.\n"
        "         GI probes update over frames: gi.budget 16384 rays per frame unless --set gives it (0: all before each frame).\n"
        "batch    many render jobs in one process: one GL context, programs compiled once (faster\n"
        "         than one process per image). A job is render's arguments: a line of JOBS.txt, or in\n"
        "         JSON [{\"args\": [\"a.gltf\", \"--size\", \"320x240\", \"-o\", \"a.png\"]}, ...] or named\n"
        "         fields {\"scene\": ..., \"output\": ..., \"size\": ..., \"camera\": ..., \"path\": ...,\n"
        "         \"set\": {\"ssao.enabled\": false}, \"raytrace\": ..., \"spp\": ..., \"seed\": ...,\n"
        "         \"animation\": ..., \"time\": ...}; {\"args\": [...], \"jobs\": [...]} puts args before\n"
        "         every job. A job's image equals `candela render` with its arguments. One backend\n"
        "         per batch (--backend, else the first job's). A failed job is reported with its\n"
        "         index and the batch goes on; exit 1 if a job failed internally, else 2 if one had\n"
        "         bad input, else 0. --timings: each job's time and the process's memory.\n"
        "merge    the sample-weighted mean of --spp-shard outputs: equal to one run with all samples.\n"
        "         Shards carry what they are shards of in their .exr header (scene, size, seed, mode,\n"
        "         spp, options); shards of another render, or one given twice, are refused (exit 2).\n"
        "farm     the tracer's big jobs as tasks for a batch scheduler (docs/farm.md).\n"
        "         reference: N tasks, each render --spp-shard K/N into DIR/shards, then\n"
        "         finish merges them into DIR/reference.exr (--batch-stats: and the per-pixel standard\n"
        "         error, DIR/reference_stderr.exr). sweep: one task per section of bench accuracy\n"
        "         (an effect on a scene), then finish writes DIR/results.csv, report.md and plots as\n"
        "         bench accuracy does. DIR gets farm.json, tasks.txt (one command per task index),\n"
        "         run-task.sh INDEX, Slurm scripts (slurm/array.sbatch, slurm/finish.sbatch,\n"
        "         submit-slurm.sh) and logs/. --sbatch ARG adds '#SBATCH ARG' (e.g. --sbatch\n"
        "         --partition=cpu); --dry-run prints the scripts and writes nothing; --submit runs\n"
        "         sbatch (the finishing job after the array, also when a task failed), --wait until\n"
        "         it ends. task DIR INDEX runs one task and skips it if its output is complete;\n"
        "         finish and status report an incomplete task with its log (exit 1); submit DIR\n"
        "         submits again (complete tasks skip). Rerunning the same farm command reuses DIR.\n"
        "error budget: --error-budget E (render, info, bench frame) chooses the cheapest of a ladder\n"
        "         of effect and knob settings whose predicted error against --raytrace path is at\n"
        "         most E (mean display difference over 4x4 blocks, 0 < E <= 1; e.g. 0.01, 0.03, 0.1)\n"
        "         for this scene and view, from a model fitted on measured scenes (built in;\n"
        "         --budget-model FILE.json replaces it). It replaces --effects (not allowed with it);\n"
        "         --set still applies over the choice. info prints every candidate's prediction,\n"
        "         the chosen one and the runner-up it rejected. render --verify also traces the\n"
        "         reference (--spp, default 256) and prints the achieved error. None predicted\n"
        "         within E: the most accurate is chosen, it says so, and the exit code stays 0.\n"
        "info     counts, bounds, cameras, lights, material variants (index, name, primitives changed),\n"
        "         the effects the scene calls for, the planned passes and reflection probes.\n"
        "compare  RMSE, relative MSE, PSNR, max difference and the pixels beyond --tolerance\n"
        "         (default 2/255) of A against B; --check exits 4 if more than --max-failing (default\n"
        "         0.001 = 0.1 %) of the pixels fail. --blocks K also compares A with a noisy reference B\n"
        "         as a viewer sees them: display values averaged over KxK blocks (mean and 99th\n"
        "         percentile of the difference) and the ratio of mean luminances.\n"
        "         --batches: statistics of independent batches of one scene (e.g. render --spp-shard\n"
        "         K/N for each K, equal sample counts) against a second batch set or a reference\n"
        "         REF (exact, or with its per-pixel standard error --ref-stderr). Per pixel and RGB\n"
        "         channel z = (mean_A - mean_B) / sqrt(se_A^2 + se_B^2), se from the batches' spread;\n"
        "         pixels_passing: all channels |z| < --z-threshold (default 5). z_of_mean: the\n"
        "         difference of the image means (luminance) over its standard error, taken from the\n"
        "         batch-to-batch spread of each batch's image mean. Non-finite pixels are left out\n"
        "         and counted. --z-map writes |z| (red at the threshold), --save-mean/--save-stderr\n"
        "         set A's mean and standard error (a reference for later). Exit 0 whatever the result.\n"
        "bench    rays: primary, AO and diffuse-bounce ray rates of the ray tracer (SCENE may be\n"
        "         generated:N triangles).\n"
        "         frame: median frame time and per-pass GPU time of each --effects variant (default\n"
        "         all and none) or, with several --path values, of each render path, measured\n"
        "         interleaved in one run (default 1280x720, 20 frames, 3 warm-up). SCENE may be\n"
        "         generated:lights:N (N point lights of range 3 over a floor with boxes),\n"
        "         generated:lights-bounded:N (the same with ranges that keep each point reached by\n"
        "         about one light at any N),\n"
        "         generated:street:N (N lamps without a range along a road: lights.cutoff's scene),\n"
        "         generated:emitters:N (N small emissive squares in place of lights-bounded's lights),\n"
        "         generated:edges (thin, high-contrast edges: the anti-aliasing scene).\n"
        "         lights: for each of --counts (default 4,16,64,256) lights of generated:lights-bounded:N\n"
        "         (--scene bounded), generated:street:N (--scene street) or generated:emitters:N\n"
        "         (--scene emitters; default counts 4,16,64): the default and the\n"
        "         speed-of-light frames' median times and the default frame's block error (4x4,\n"
        "         display) against --raytrace path at --spp (default 32) samples (default 320x180).\n"
        "         accuracy: every effect's knob sweep, timed and compared with the ray tracer's\n"
        "         reference: DIR/results.csv, report.md, plots and image strips (--quick: small, CI).\n"
        "         error-budget: every candidate of --error-budget's ladder measured on each SCENE\n"
        "         (error against --raytrace path, frame time against the speed-of-light frame; default\n"
        "         160x120, reference 512 spp) into --csv; --fit fits the model from such files;\n"
        "         --evaluate prints the choices' achieved errors per budget (docs/error-budget.md).\n"
        "         reload: median time from saving a shader file to the first frame drawn with the\n"
        "         rebuilt programs (a copy of the shaders is edited; default 1280x720, 10 saves).\n"
        "\n"
        "exit codes: 0 ok, 1 internal error, 2 bad input (file, option), 3 no usable OpenGL 4.5,\n"
        "            4 compare --check: images differ beyond the tolerance.\n";
    return text;
}
}  // namespace

void print_usage() { std::fputs(usage_text().c_str(), stdout); }

bool print_command_usage(const std::string& command) {
    // The command's part of the whole text: its usage lines ("  candela COMMAND ..." and their
    // continuations), the paragraphs that start with its name, and the exit codes.
    const std::string text = usage_text();
    std::vector<std::string> lines;
    for (size_t a = 0; a < text.size();) {
        const size_t b = text.find('\n', a);
        lines.push_back(text.substr(a, b - a));
        a = b == std::string::npos ? text.size() : b + 1;
    }
    const auto starts = [](const std::string& line, const std::string& prefix) { return line.compare(0, prefix.size(), prefix) == 0; };
    const std::string usage_prefix = "  candela " + command;
    std::string usage, about, exit_codes;
    bool in_usage = false, in_about = false, in_exit = false;
    for (const std::string& line : lines) {
        if (starts(line, "  candela ")) {
            in_usage = starts(line, usage_prefix) &&
                       (line.size() == usage_prefix.size() || line[usage_prefix.size()] == ' ' || line[usage_prefix.size()] == '|');
            if (!in_usage && starts(line, "  candela render|info|view|bench frame") &&
                (command == "render" || command == "info" || command == "view" || command == "bench"))
                in_usage = true;
        } else if (!starts(line, "   ")) {
            in_usage = false;
        }
        if (!line.empty() && line[0] != ' ') {
            in_about = starts(line, command + " ") ||
                       (starts(line, "error budget:") && (command == "render" || command == "info" || command == "view" || command == "bench"));
            in_exit = starts(line, "exit codes:");
        } else if (line.empty()) {
            in_about = in_exit = false;
        }
        if (in_usage) usage += line + "\n";
        if (in_about) about += line + "\n";
        if (in_exit) exit_codes += line + "\n";
    }
    if (usage.empty()) return false;
    std::fputs(("usage:\n" + usage + (about.empty() ? "" : "\n" + about) + "\n" + exit_codes).c_str(), stdout);
    return true;
}

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

int parse_int(const std::string& option, const std::string& text, int lo, int hi) {
    try {
        size_t used = 0;
        const long v = std::stol(text, &used);
        if (used == text.size() && v >= lo && v <= hi) return static_cast<int>(v);
    } catch (const std::exception&) {
    }
    throw bad_input(option + " '" + text + "' must be an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
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

Backend backend_option(const Parsed& p, bool quote_value) {
    if (!p.has("--backend")) return Backend::auto_select;
    const auto b = parse_backend(p.get("--backend"));
    if (!b || *b == Backend::glfw)
        throw bad_input(quote_value ? "--backend '" + p.get("--backend") + "' must be auto, egl or osmesa"
                                    : "--backend must be auto, egl or osmesa");
    return *b;
}

fs::path shader_dir_option(const Parsed& p) {
    if (!p.has("--shader-dir")) return ShaderLibrary::default_root();
    const fs::path dir = p.get("--shader-dir");
    if (!fs::is_directory(dir)) throw bad_input("--shader-dir " + dir.string() + ": not a directory");
    return dir;
}

std::string format_number(const char* format, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, format, v);
    return buf;
}

void log_origin(const Scene& scene, const char* why) {
    char where[200];
    std::snprintf(where, sizeof where, "origin: (%.17g, %.17g, %.17g): %s, rendered relative to this point", scene.origin.x,
                  scene.origin.y, scene.origin.z, why);
    log::info(where);
}

void anchor_scene(Scene& scene, const std::string& camera, float aspect, int animation, float time) {
    if (anchor_at_camera(scene, scene.select_camera(camera, aspect), animation, time))
        log_origin(scene, "at the camera, which stands far from the scene's origin compared with its near plane");
}

Scene load_scene(const std::string& path, bool strict) {
    if (path == "generated:dof") return make_dof_scene();
    if (path == "generated:edges") return make_edges_scene();
    if (path == "generated:materials") return make_materials_scene();
    if (path == "generated:motion") return make_motion_scene();
    if (path.rfind("generated:skinned:", 0) == 0) {
        const std::string n = path.substr(18);
        if (n.empty() || n.size() > 8 || n.find_first_not_of("0123456789") != std::string::npos || std::stoul(n) < 64)
            throw bad_input(path + ": expected generated:skinned:N with 64 <= N < 1e8 triangles");
        return make_skinned_scene(std::stoul(n));
    }
    if (path.rfind("generated:random:", 0) == 0) {
        const std::string n = path.substr(17);
        if (n.empty() || n.size() > 10 || n.find_first_not_of("0123456789") != std::string::npos || std::stoull(n) > 4294967295ull)
            throw bad_input(path + ": expected generated:random:SEED with SEED an integer from 0 to 4294967295");
        return make_random_scene(static_cast<std::uint32_t>(std::stoull(n)));
    }
    for (const bool bounded : {false, true}) {
        const std::string prefix = bounded ? "generated:lights-bounded:" : "generated:lights:";
        if (path.rfind(prefix, 0) != 0) continue;
        const std::string n = path.substr(prefix.size());
        if (n.empty() || n.size() > 6 || n.find_first_not_of("0123456789") != std::string::npos || std::stoul(n) < 1)
            throw bad_input(path + ": expected " + prefix + "N with 1 <= N < 1e6 point lights");
        return make_many_lights_scene(static_cast<int>(std::stoul(n)), bounded);
    }
    if (path.rfind("generated:emitters:", 0) == 0) {
        const std::string n = path.substr(19);
        if (n.empty() || n.size() > 6 || n.find_first_not_of("0123456789") != std::string::npos || std::stoul(n) < 1)
            throw bad_input(path + ": expected generated:emitters:N with 1 <= N < 1e6 emitters");
        return make_emitters_scene(static_cast<int>(std::stoul(n)));
    }
    if (path.rfind("generated:street:", 0) == 0) {
        const std::string n = path.substr(17);
        if (n.empty() || n.size() > 6 || n.find_first_not_of("0123456789") != std::string::npos || std::stoul(n) < 1)
            throw bad_input(path + ": expected generated:street:N with 1 <= N < 1e6 lamps");
        return make_street_scene(static_cast<int>(std::stoul(n)));
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
    if (scene.origin != glm::dvec3(0.0)) log_origin(scene, "far from the file's origin");
    return scene;
}

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

const std::vector<std::string> kSceneSetupOptions = {"--size", "--backend", "--camera", "--environment", "--lighting",
                                                     "--effects", "--set", "--frames", "--warmup", "--path",
                                                     "--output-buffer", "--shader-dir", "--animation", "--time", "--variant"};
const std::vector<std::string> kSceneSetupFlags = {"--debug-gl", "--strict", "--verify-state", "--quiet"};

SceneSetup setup_scene(const Parsed& p, const std::string& scene_path, int default_w, int default_h) {
    SceneSetup s;
    s.gl_errors_before = gl::debug_error_count();
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
        const std::optional<RenderPath> parsed = parse_choice(kRenderPaths, path);
        if (!parsed) throw bad_input("--path '" + path + "' must be auto, forward or deferred");
        s.options.settings.path = *parsed;
    }
    if (p.has("--output-buffer")) {
        const std::string b = p.get("--output-buffer");
        if (b != "radiance" && b != "visibility" && b != "ao" && b != "indirect")
            throw bad_input("--output-buffer '" + b + "' must be radiance, visibility (of light --set debug.light=K), ao or indirect");
        s.options.settings.debug.view = b == "radiance" ? DebugView::none : *parse_choice(kDebugViews, b);
    }
    apply_knobs(s.options.settings, p.all("--set"));
    s.options.verify_state = p.flags.count("--verify-state") > 0;
    s.backend = backend_option(p, true);
    // CANDELA_DEBUG_GL=1 does the same as --debug-gl; the test suite sets it for every command.
    const char* debug_env = std::getenv("CANDELA_DEBUG_GL");
    s.debug = p.flags.count("--debug-gl") > 0 || (debug_env && std::string(debug_env) == "1");
    const auto t0 = std::chrono::steady_clock::now();
    s.scene = load_scene(scene_path, p.flags.count("--strict") > 0);
    // Animation: --animation N|NAME and --time T pose the scene (render also takes
    // --time A:B, a sequence: the scene is posed at A here). --time alone plays animation 0;
    // --animation alone poses at time 0; neither: the rest pose (skins and morph weights applied).
    if (p.has("--time")) {
        const std::string t = p.get("--time");
        const size_t colon = t.find(':');
        s.time_first = parse_float("--time", t.substr(0, colon), 0.0f, 1e6f);
        s.time_last = colon == std::string::npos ? s.time_first : parse_float("--time", t.substr(colon + 1), 0.0f, 1e6f);
        if (s.time_last < s.time_first) throw bad_input("--time '" + t + "': the end is before the start");
    }
    if (p.has("--animation") && p.get("--animation") == "none") {  // the rest pose, even with --time
        s.options.animation = -1;
    } else if (p.has("--animation")) s.options.animation = find_animation(s.scene, p.get("--animation"));
    else if (p.has("--time")) {
        if (s.scene.animations.empty()) throw bad_input(scene_path + ": --time needs an animation, and the scene has none");
        s.options.animation = 0;
    }
    s.options.time = s.time_first;
    if (p.has("--variant")) select_variant(s.scene, find_variant(s.scene, p.get("--variant")));
    if (s.options.animation >= 0) pose_scene(s.scene, s.options.animation, s.options.time);
    anchor_scene(s.scene, s.options.camera, static_cast<float>(s.options.width) / static_cast<float>(s.options.height),
                 s.options.animation, s.options.time);
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

void finish_lighting(SceneSetup& s, const ShaderLibrary& shaders) {
    if (!s.lighting.check_view) return;
    const float aspect = static_cast<float>(s.options.width) / static_cast<float>(s.options.height);
    complete_lighting(s.scene, s.lighting, shaders, s.scene.select_camera(s.options.camera, aspect), aspect);
    if (s.lighting.environment_added) log::warn("lighting: " + s.lighting.reason);
    else log::info("lighting: " + s.lighting.reason);
}

void warn_idle_knobs(const Parsed& p, const Features& features) {
    for (const std::string& assignment : p.all("--set")) {
        const std::string name = assignment.substr(0, assignment.find('='));
        for (const Effect* e : effect_registry())
            for (const std::string& group : e->knob_groups())
                if (name.rfind(group + ".", 0) == 0) {
                    const EffectDecision& d = features.decision(e->name());
                    if (!d.planned) log::warn("--set " + assignment + " has no effect: " + e->name() + " is " + d.reason);
                }
    }
}

bool mip_worker_wanted() {
    const char* v = std::getenv("CANDELA_MIP_WORKER");
    return !(v && std::string(v) == "0");
}

int check_gl_errors(const SceneSetup& s) {
    if (const int errors = gl::debug_error_count() - s.gl_errors_before; s.debug && errors > 0) {
        std::fprintf(stderr, "candela: error: %d GL error(s) (see above)\n", errors);
        return static_cast<int>(ExitCode::internal);
    }
    return 0;
}

}  // namespace candela::cli
