// Golden-image check of sample scenes on one backend:
//   candela_golden SCENE.gltf GOLDEN.png OUT_DIR --backend egl|osmesa [--size WxH] [--update]
//                  [--path forward|deferred|auto] [--set KNOB=V] [--animation N|NAME --time T]
//                  [--orbit DEGREES]
//   candela_golden --jobs FILE   (one golden per line: the arguments above, '#' comments)
// --animation/--time pose the scene; --orbit turns the framing camera about the bounds'
// vertical axis (a side view of an animated model).
// Renders with GL debug output on; fails on any GL error, any non-finite pixel, or more than
// 0.1 % of pixels differing by more than 2/255 from the golden (docs/testing.md).
// On failure the actual image and a heat-map diff are written to OUT_DIR and their paths printed.
// --update (used only by the `update-goldens` target) overwrites the golden instead.
// --jobs (the ctest golden suites): every line's golden in one process, one GL context
// and one set of compiled programs (llvmpipe compiles a program's code at its first draw: about
// half of a one-golden process); all lines name the same backend. Each golden is reported by
// name ("ok NAME" or "FAIL NAME: why"); exit 1 if any failed, 2 for a bad jobs file.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "core/command_line.hpp"
#include "core/error.hpp"
#include "gl/debug.hpp"
#include "image/image.hpp"
#include "platform/context.hpp"
#include "render/program_cache.hpp"
#include "render/still.hpp"
#include "scene/animation.hpp"
#include "scene/gltf_loader.hpp"
#include "scene/origin.hpp"
#include "rt/view_lighting.hpp"
#include "scene/lighting.hpp"

namespace fs = std::filesystem;
using namespace candela;

namespace {
constexpr double kTolerance = 2.0 / 255.0;
constexpr double kMaxFailingFraction = 0.001;

struct GoldenJob {
    fs::path scene_path, golden, out_dir;
    Backend backend = Backend::egl;
    StillOptions options;
    bool update = false;
    std::vector<std::string> knobs;
    std::string animation;
    float time = 0.0f, orbit = 0.0f;
};

// The arguments of one golden (after the program name); "" or the message of a bad argument.
std::string parse_job(const std::vector<std::string>& args, GoldenJob& job) {
    if (args.size() < 3) return "needs SCENE GOLDEN.png OUT_DIR";
    job.scene_path = args[0];
    job.golden = args[1];
    job.out_dir = args[2];
    job.options.width = job.options.height = 256;
    for (size_t i = 3; i < args.size(); ++i) {
        const std::string& a = args[i];
        const bool value = i + 1 < args.size();
        if (a == "--update") job.update = true;
        else if (a == "--backend" && value) job.backend = parse_backend(args[++i]).value_or(Backend::egl);
        else if (a == "--size" && value) std::sscanf(args[++i].c_str(), "%dx%d", &job.options.width, &job.options.height);
        else if (a == "--path" && value) job.knobs.push_back("render.path=" + args[++i]);  // forward|deferred: one golden for both
        else if (a == "--set" && value) job.knobs.push_back(args[++i]);
        else if (a == "--animation" && value) job.animation = args[++i];
        else if (a == "--time" && value) job.time = std::strtof(args[++i].c_str(), nullptr);
        else if (a == "--orbit" && value) job.orbit = std::strtof(args[++i].c_str(), nullptr);
        else return "unknown argument '" + a + "'";
    }
    return "";
}

// What names a golden in messages and output files: GOLDEN's stem, backend, render path.
std::string job_name(const GoldenJob& job) {
    return job.golden.stem().string() + "." + to_string(job.backend) + "." + choice_name(kRenderPaths, job.options.settings.path);
}

// Renders one golden with the current context and compares it; prints "FAIL NAME: ..." lines.
// Returns the exit code of this golden (0 ok, 1 failed, 2 bad input).
int run_job(GoldenJob& job, const ShaderLibrary& shaders, ProgramCache* programs) {
    const int gl_errors_before = gl::debug_error_count();
    std::string name = job.golden.stem().string() + "." + to_string(job.backend);
    try {
        StillOptions& options = job.options;
        apply_knobs(options.settings, job.knobs);
        name = job_name(job);
        Scene scene = load_gltf(job.scene_path);
        if (!job.animation.empty()) {
            options.animation = find_animation(scene, job.animation);
            options.time = job.time;
            pose_scene(scene, options.animation, job.time);
        }
        if (job.orbit != 0.0f) {
            Camera cam = framing_camera(scene.world_bounds());
            const glm::vec3 c = scene.world_bounds().center();
            cam.world = glm::translate(glm::mat4(1.0f), c) * glm::rotate(glm::mat4(1.0f), glm::radians(job.orbit), glm::vec3(0, 1, 0)) *
                        glm::translate(glm::mat4(1.0f), -c) * cam.world;
            cam.name = "orbit";
            scene.cameras.insert(scene.cameras.begin(), cam);  // the first camera is the default
        }
        // As `candela render`: a file without lights gets the default rig (--lighting auto).
        const float aspect = static_cast<float>(options.width) / static_cast<float>(options.height);
        anchor_at_camera(scene, scene.select_camera(options.camera, aspect), options.animation, options.time);
        LightingChoice lighting = apply_lighting(scene, LightingMode::auto_select, scene.select_camera(options.camera, aspect));
        complete_lighting(scene, lighting, shaders, scene.select_camera(options.camera, aspect), aspect);
        options.output = FrameOutput::display;  // the GPU tonemap pass, as `candela render x.png`
        options.verify_state = true;
        options.programs = programs;
        const StillResult result = render_still(scene, shaders, options);
        int failures = 0;
        if (const int errors = gl::debug_error_count() - gl_errors_before; errors > 0) {
            std::fprintf(stderr, "FAIL %s: %d GL error(s) during the render\n", name.c_str(), errors);
            ++failures;
        }
        // The path asked for is the path that ran (one golden for both paths: each must be drawn
        // by its own passes).
        const char* path_pass = options.settings.path == RenderPath::deferred  ? "deferred_lighting"
                                : options.settings.path == RenderPath::forward ? "forward_opaque"
                                                                               : nullptr;
        if (path_pass && std::none_of(result.report.passes.begin(), result.report.passes.end(),
                                      [&](const PassStats& p) { return p.name == path_pass; })) {
            std::fprintf(stderr, "FAIL %s: the %s path ran without its pass %s\n", name.c_str(),
                         choice_name(kRenderPaths, options.settings.path), path_pass);
            ++failures;
        }
        if (const size_t bad = count_nonfinite(result.radiance)) {
            std::fprintf(stderr, "FAIL %s: %zu non-finite values in the rendered radiance\n", name.c_str(), bad);
            ++failures;
        }
        fs::create_directories(job.out_dir);
        const fs::path actual_path = job.out_dir / (name + ".actual.png");
        write_display_rgba8(actual_path, result.display, options.width, options.height);
        if (job.update) {
            if (failures) return 1;
            fs::create_directories(job.golden.parent_path());
            fs::copy_file(actual_path, job.golden, fs::copy_options::overwrite_existing);
            std::printf("updated %s\n", job.golden.string().c_str());
            return 0;
        }
        // Compare the PNG as written (8-bit quantised) with the golden.
        const ImageF actual = read_image(actual_path);
        const ImageF expected = read_image(job.golden);
        if (actual.width != expected.width || actual.height != expected.height) {
            std::fprintf(stderr, "FAIL %s: %s is %dx%d, the render is %dx%d\n", name.c_str(), job.golden.string().c_str(),
                         expected.width, expected.height, actual.width, actual.height);
            return 1;
        }
        const CompareResult r = compare(actual, expected, kTolerance);
        std::printf("%s vs %s: rmse %.6f, max %.4f, %zu pixels (%.4f %%) beyond %.4f\n", actual_path.filename().c_str(),
                    job.golden.filename().c_str(), r.rmse, r.max_abs, r.failing_pixels, 100.0 * r.failing_fraction, kTolerance);
        if (r.failing_fraction > kMaxFailingFraction || r.nonfinite) {
            const fs::path diff_path = job.out_dir / (name + ".diff.png");
            write_display_image(diff_path, heatmap(actual, expected, 8.0 * kTolerance));
            std::fprintf(stderr, "FAIL %s: beyond tolerance (max %.2f %% of pixels)\n  actual:  %s\n  heatmap: %s\n", name.c_str(),
                         100.0 * kMaxFailingFraction, fs::absolute(actual_path).c_str(), fs::absolute(diff_path).c_str());
            ++failures;
        }
        return failures ? 1 : 0;
    } catch (const Error& e) {
        std::fprintf(stderr, "FAIL %s: %s\n", name.c_str(), e.what());
        return static_cast<int>(e.code());
    }
}


ContextResult open_context(Backend backend) {
    ContextOptions ctx_options;
    ctx_options.debug = true;
    ContextResult ctx = create_context(backend, ctx_options);
    if (!ctx.context) std::fprintf(stderr, "FAIL: no usable OpenGL: %s\n", ctx.error.c_str());
    else std::printf("device: %s (%s)\n", ctx.context->device_string().c_str(), to_string(backend));
    return ctx;
}

int run_jobs_file(const fs::path& file) {
    std::ifstream in(file);
    if (!in) {
        std::fprintf(stderr, "candela_golden: %s: cannot read the jobs file\n", file.c_str());
        return 2;
    }
    std::vector<GoldenJob> jobs;
    std::string line;
    for (int line_no = 1; std::getline(in, line); ++line_no) {
        std::vector<std::string> args;
        try {
            args = split_command_line(line);
        } catch (const Error& e) {
            std::fprintf(stderr, "candela_golden: %s:%d: %s\n", file.c_str(), line_no, e.what());
            return 2;
        }
        if (args.empty()) continue;
        GoldenJob job;
        if (const std::string error = parse_job(args, job); !error.empty()) {
            std::fprintf(stderr, "candela_golden: %s:%d: %s\n", file.c_str(), line_no, error.c_str());
            return 2;
        }
        if (!jobs.empty() && job.backend != jobs.front().backend) {
            std::fprintf(stderr, "candela_golden: %s:%d: --backend %s, the file's first golden has %s (one backend per file)\n",
                         file.c_str(), line_no, to_string(job.backend), to_string(jobs.front().backend));
            return 2;
        }
        jobs.push_back(std::move(job));
    }
    if (jobs.empty()) {
        std::fprintf(stderr, "candela_golden: %s: no goldens\n", file.c_str());
        return 2;
    }
    ContextResult ctx = open_context(jobs.front().backend);
    if (!ctx.context) return 3;
    const ShaderLibrary shaders(ShaderLibrary::default_root());
    ProgramCache programs(shaders);
    std::vector<std::string> failed;
    int worst = 0;
    for (GoldenJob& job : jobs) {
        const auto t0 = std::chrono::steady_clock::now();
        const std::clock_t c0 = std::clock();
        const int rc = run_job(job, shaders, &programs);
        const double cpu_ms = 1000.0 * static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
        const double wall_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        const std::string name = job_name(job);
        std::printf("%s %s (%.0f ms, CPU %.0f ms)\n", rc == 0 ? "ok" : "FAILED", name.c_str(), wall_ms, cpu_ms);
        std::fflush(stdout);
        if (rc != 0) {
            failed.push_back(name);
            worst = worst == 0 || rc == 1 ? rc : worst;  // a failed comparison/render (1) over bad input (2)
        }
    }
    std::printf("%zu golden(s) from %s: %zu ok, %zu failed\n", jobs.size(), file.filename().c_str(), jobs.size() - failed.size(),
                failed.size());
    for (const std::string& name : failed) std::fprintf(stderr, "FAIL %s\n", name.c_str());
    return worst;
}
}  // namespace

int main(int argc, char** argv) {
    if (argc == 3 && std::string(argv[1]) == "--jobs") return run_jobs_file(argv[2]);
    if (argc < 4) {
        std::fprintf(stderr, "usage: candela_golden SCENE GOLDEN.png OUT_DIR --backend B [--path forward|deferred] [--size WxH] [--set KNOB=V] [--update]\n"
                             "       candela_golden --jobs FILE   (one golden's arguments per line)\n");
        return 2;
    }
    GoldenJob job;
    if (const std::string error = parse_job(std::vector<std::string>(argv + 1, argv + argc), job); !error.empty()) {
        std::fprintf(stderr, "candela_golden: %s\n", error.c_str());
        return 2;
    }
    ContextResult ctx = open_context(job.backend);
    if (!ctx.context) return 3;
    return run_job(job, ShaderLibrary(ShaderLibrary::default_root()), nullptr);
}
