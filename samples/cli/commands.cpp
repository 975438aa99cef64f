#include "commands.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <optional>

#include "core/error.hpp"
#include "core/log.hpp"
#include "gl/debug.hpp"
#include "image/image.hpp"
#include "platform/context.hpp"
#include "render/still.hpp"
#include "scene/features.hpp"
#include "scene/gltf_loader.hpp"

namespace candela::cli {
namespace fs = std::filesystem;

void print_usage() {
    std::fputs(
        "Candela: an OpenGL 4.5 renderer whose approximations are checked against its own ray tracer.\n"
        "\n"
        "usage:\n"
        "  candela render SCENE -o OUT.(png|exr) [--size WxH] [--backend auto|egl|osmesa]\n"
        "                 [--camera N|NAME] [--exposure EV] [--environment FILE] [--debug-gl] [--timings]\n"
        "                 [--strict]\n"
        "  candela info SCENE [--strict]\n"
        "  candela compare A B [--heatmap OUT.png] [--tolerance T] [--max-failing F] [--check]\n"
        "\n"
        "render   SCENE (.gltf/.glb) to OUT: .exr holds linear radiance; .png is exposure + ACES + sRGB.\n"
        "         --size WxH (default 512x512), --backend (default auto: EGL, then OSMesa),\n"
        "         --camera glTF camera index or name (default: the first, else a framing camera),\n"
        "         --exposure EV for .png (default 0), --environment FILE (.hdr/.exr, equirectangular)\n"
        "         replaces the scene's environment, --debug-gl logs GL debug output and fails on GL errors,\n"
        "         --timings prints where the time went, --strict treats loader warnings (missing\n"
        "         texture, skipped primitive, repaired data) as errors (exit 2).\n"
        "info     counts, bounds, cameras, lights and the features the scene calls for.\n"
        "compare  RMSE, relative MSE, PSNR, max difference and the pixels beyond --tolerance\n"
        "         (default 2/255) of A against B; --check exits 4 if more than --max-failing (default\n"
        "         0.001 = 0.1 %) of the pixels fail.\n"
        "\n"
        "exit codes: 0 ok, 1 internal error, 2 bad input (file, option), 3 no usable OpenGL 4.5,\n"
        "            4 compare --check: images differ beyond the tolerance.\n",
        stdout);
}

namespace {

// Options of the form --name VALUE; positional arguments kept in order.
struct Parsed {
    std::vector<std::string> positional;
    std::map<std::string, std::string> options;
    std::map<std::string, bool> flags;
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
            p.options[name] = value;
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
    const int before = log::warning_count();
    Scene scene = load_gltf(path);
    const int warnings = log::warning_count() - before;
    if (strict && warnings > 0)
        throw bad_input(path + ": " + std::to_string(warnings) + " loader warning(s) (see above) and --strict is set");
    return scene;
}

}  // namespace

int cmd_render(const Args& args) {
    const Parsed p = parse(args, {"-o", "--output", "--size", "--backend", "--camera", "--exposure", "--environment"},
                           {"--debug-gl", "--timings", "--quiet", "--strict"});
    if (p.positional.size() != 1) throw bad_input("render needs exactly one SCENE (got " + std::to_string(p.positional.size()) + ")");
    std::string out = p.options.count("-o") ? p.options.at("-o") : p.options.count("--output") ? p.options.at("--output") : "";
    if (out.empty()) throw bad_input("render needs -o OUT.png or -o OUT.exr");
    const fs::path out_path(out);
    {
        std::string e = out_path.extension().string();
        for (auto& c : e) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
        if (e != ".png" && e != ".exr") throw bad_input(out + ": the output must be .png or .exr");
    }
    if (p.flags.count("--quiet")) log::set_level(log::Level::warn);
    StillOptions options;
    if (p.options.count("--size")) parse_size(p.options.at("--size"), options.width, options.height);
    if (p.options.count("--camera")) options.camera = p.options.at("--camera");
    const float exposure = p.options.count("--exposure") ? parse_float("--exposure", p.options.at("--exposure"), -32, 32) : 0.0f;
    Backend backend = Backend::auto_select;
    if (p.options.count("--backend")) {
        const auto b = parse_backend(p.options.at("--backend"));
        if (!b || *b == Backend::glfw) throw bad_input("--backend '" + p.options.at("--backend") + "' must be auto, egl or osmesa");
        backend = *b;
    }

    const auto t_start = std::chrono::steady_clock::now();
    Scene scene = load_scene(p.positional[0], p.flags.count("--strict") > 0);
    if (p.options.count("--environment")) {
        const fs::path env = p.options.at("--environment");
        if (!fs::is_regular_file(env)) throw bad_input(env.string() + ": --environment: no such file");
        scene.environment.map = env;
        scene.environment.intensity = 1.0f;
    }
    const double load_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t_start).count();

    const bool debug = p.flags.count("--debug-gl") > 0;
    auto t0 = std::chrono::steady_clock::now();
    ContextOptions ctx_options;
    ctx_options.debug = debug;
    ContextResult ctx = create_context(backend, ctx_options);
    if (!ctx.context) {
        std::fprintf(stderr, "candela: error: no usable OpenGL: %s\n", ctx.error.c_str());
        return static_cast<int>(ExitCode::no_gl);
    }
    const double context_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    log::info(std::string("backend ") + to_string(ctx.context->backend()) + ": " + ctx.context->device_string());

    const ShaderLibrary shaders(ShaderLibrary::default_root());
    const StillResult result = render_still(scene, shaders, options);
    const std::size_t bad = count_nonfinite(result.radiance);
    if (bad) log::warn(out + ": " + std::to_string(bad) + " non-finite values in the rendered radiance (written as 0 in .png)");
    t0 = std::chrono::steady_clock::now();
    write_image(out_path, result.radiance, exposure);
    const double write_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    if (p.flags.count("--timings"))
        std::fprintf(stderr,
                     "candela: timings (ms): load %.1f, context %.1f, upload %.1f, shaders %.1f, frame %.1f, "
                     "readback %.1f, write %.1f; %d draw calls, %zu triangles\n",
                     load_ms, context_ms, result.upload_ms, result.shader_ms, result.frame_ms, result.readback_ms,
                     write_ms, result.stats.draw_calls, result.stats.triangles);
    if (debug && gl::debug_error_count() > 0) {
        std::fprintf(stderr, "candela: error: %d GL error(s) during the render (see above)\n", gl::debug_error_count());
        return static_cast<int>(ExitCode::internal);
    }
    return 0;
}

int cmd_info(const Args& args) {
    const Parsed p = parse(args, {}, {"--strict"});
    if (p.positional.size() != 1) throw bad_input("info needs exactly one SCENE");
    const Scene scene = load_scene(p.positional[0], p.flags.count("--strict") > 0);
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
    if (scene.cameras.empty()) std::printf("  (none: a framing camera is computed from the bounds)\n");
    std::printf("environment: %s\n", !scene.environment.map.empty() ? scene.environment.map.string().c_str()
                                     : scene.environment.present()
                                         ? ("constant (" + fmt("%.3g", scene.environment.radiance.r) + ", " +
                                            fmt("%.3g", scene.environment.radiance.g) + ", " +
                                            fmt("%.3g", scene.environment.radiance.b) + ")").c_str()
                                         : "none");
    std::printf("features:\n");
    const SceneFeatures f = analyze_features(scene);
    for (const Feature* feat : f.all())
        std::printf("  %-22s %-4s %s\n", (feat->name + ":").c_str(), feat->needed ? "on" : "off", feat->reason.c_str());
    return 0;
}

int cmd_compare(const Args& args) {
    const Parsed p = parse(args, {"--heatmap", "--tolerance", "--max-failing"}, {"--check"});
    if (p.positional.size() != 2) throw bad_input("compare needs two images A B");
    const double tolerance = p.options.count("--tolerance") ? parse_float("--tolerance", p.options.at("--tolerance"), 0, 1e30f) : 2.0 / 255.0;
    const double max_failing = p.options.count("--max-failing") ? parse_float("--max-failing", p.options.at("--max-failing"), 0, 1) : 0.001;
    const ImageF a = read_image(p.positional[0]);
    const ImageF b = read_image(p.positional[1]);
    if (a.width != b.width || a.height != b.height)
        throw bad_input(p.positional[0] + " is " + std::to_string(a.width) + "x" + std::to_string(a.height) + " but " +
                        p.positional[1] + " is " + std::to_string(b.width) + "x" + std::to_string(b.height));
    const CompareResult r = compare(a, b, tolerance);
    std::printf("rmse %.6g\nrelative_mse %.6g\npsnr %.3f dB\nmax_abs %.6g\nfailing_pixels %zu (%.4f %%, tolerance %.6g)\nnonfinite %zu\n",
                r.rmse, r.relative_mse, r.psnr, r.max_abs, r.failing_pixels, 100.0 * r.failing_fraction, tolerance,
                r.nonfinite);
    if (p.options.count("--heatmap")) write_display_image(p.options.at("--heatmap"), heatmap(a, b, std::max(tolerance * 4, 1e-6)));
    if (p.flags.count("--check") && (r.failing_fraction > max_failing || r.nonfinite > 0)) return 4;
    return 0;
}

}  // namespace candela::cli
