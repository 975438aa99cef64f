// `candela render`: one still image of a scene, by the rasterizer or (--raytrace) the ray tracer.
#include "commands.hpp"

#include <cctype>
#include <chrono>
#include <cstdint>
#include <cmath>
#include <cstdio>

#include <unistd.h>

#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "image/image_io.hpp"
#include "rt/tracer_options.hpp"
#include "core/log.hpp"
#include "image/image.hpp"
#include "options.hpp"
#include "budget.hpp"
#include "accuracy/error_budget_measure.hpp"
#include "render_job.hpp"
#include "shards.hpp"
#include "render/stats.hpp"
#include "render/still.hpp"
#include "rt/ray_tracer.hpp"
#include "scene/animation.hpp"

namespace candela::cli {
namespace fs = std::filesystem;

namespace {

// --raytrace MODE: the image comes from the compute-shader ray tracer. Its options come from the
// command line and from the rt.* knobs, debug.light (visibility mode) and the AO radius.
int raytrace(const Parsed& p, SceneSetup& s, const fs::path& out_path, float exposure) {
    rt::Options o = rt::tracer_options(s.options.settings);
    for (const std::string& assignment : p.all("--set"))
        if (!rt::tracer_reads_knob(assignment.substr(0, assignment.find('='))))
            log::warn("--set " + assignment + " has no effect on --raytrace (the tracer reads rt.*, camera.*, ao.radius and debug.light)");
    const auto mode = rt::parse_mode(p.get("--raytrace"));
    if (!mode) throw bad_input("--raytrace '" + p.get("--raytrace") + "' must be whitted, path, direct, indirect, ao, primary or visibility");
    o.mode = *mode;
    if (p.has("--spp")) o.spp = parse_int("--spp", p.get("--spp"), 1, 1 << 24);
    if (p.has("--max-depth")) o.max_depth = parse_int("--max-depth", p.get("--max-depth"), 0, rt::kUnboundedDepth);
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
    o.progress = true;
    // Motion blur: each time slice poses the scene at its time in the shutter.
    const ShutterInterval shutter = shutter_interval(s.options.time, s.options.settings.camera.shutter, s.options.settings.camera.fps);
    if (s.options.animation >= 0 && !shutter.instant()) {
        const int animation = s.options.animation;
        Scene& scene = s.scene;
        o.pose_at = [&scene, animation, shutter](float u) { pose_scene(scene, animation, shutter.open + u * (shutter.close - shutter.open)); };
    }
    const ShaderLibrary shaders(s.shader_dir);
    GpuScene gpu(s.scene);
    rt::RayTracer tracer(shaders, s.scene, gpu, o);
    const float aspect = static_cast<float>(s.options.width) / static_cast<float>(s.options.height);
    // The camera with --set camera.aperture / camera.focus_distance over its own lens.
    rt::Result r = tracer.render(with_lens(s.scene.select_camera(s.options.camera, aspect), s.options.settings), s.options.width,
                                 s.options.height);
    const rt::BvhStats& b = tracer.scene().geometry().bvh.stats;
    log::info(std::string("ray traced '") + rt::to_string(o.mode) + "' [" + r.defines + "]: " + std::to_string(r.samples) +
              " spp in " + format_number("%.1f", r.trace_ms) + " ms; BVH " + std::to_string(b.node_count) + " nodes, depth " +
              std::to_string(b.max_depth) + ", SAH " + format_number("%.2f", b.sah_cost) + ", built in " + format_number("%.1f", b.build_ms) + " ms" +
              (r.stopped_early ? " (stopped by --time-limit)" : ""));
    if (r.nonfinite_samples) log::warn(std::to_string(r.nonfinite_samples) + " non-finite samples were replaced by 0");
    // What the image is a shard of (.exr header): merges and `candela farm` check it (shards.hpp).
    r.image.tags = shard_tags(p, rt::to_string(o.mode), o.seed, o.spp, o.shard, o.shard_count, s.options.width, s.options.height);
    write_image(out_path, r.image, exposure);
    return check_gl_errors(s);
}

// The verification reference of --error-budget E --verify: --raytrace path at --spp (default 256)
// from --seed (default 1), as two halves.
budget::Reference verify_reference(const Parsed& p, const SceneSetup& s, const ShaderLibrary& shaders) {
    const int spp = p.has("--spp") ? parse_int("--spp", p.get("--spp"), 2, 1 << 24) : 256;
    const std::uint32_t seed = p.has("--seed") ? static_cast<std::uint32_t>(parse_int("--seed", p.get("--seed"), 0, 2147483646)) : 1;
    const float aspect = static_cast<float>(s.options.width) / static_cast<float>(s.options.height);
    const Camera camera = with_lens(s.scene.select_camera(s.options.camera, aspect), s.options.settings);
    return budget::path_reference(s.scene, shaders, camera, s.options.width, s.options.height, spp, seed);
}

void print_achieved(double achieved, double budget, double predicted, const budget::Reference& ref) {
    std::printf("achieved error: %.4f (budget %.4g, predicted at most %.4f; against --raytrace path at %d spp, whose own noise "
                "moves it by about %.4f): %s\n",
                achieved, budget, predicted, ref.spp, ref.noise, achieved <= budget ? "within the budget" : "above the budget");
}

// --error-budget E where no raster candidate is predicted within E: the tracer rung renders the
// still (budget::trace_within), then --verify as for a raster frame.
int render_traced(const Parsed& p, SceneSetup& s, const ShaderLibrary& shaders, const BudgetRequest& req, const fs::path& out_path,
                  float exposure, bool verify) {
    for (const std::string& assignment : p.all("--set"))
        if (!rt::tracer_reads_knob(assignment.substr(0, assignment.find('='))))
            log::warn("--set " + assignment + " has no effect on the traced frame (the tracer reads rt.*, camera.*, ao.radius and debug.light)");
    const float aspect = static_cast<float>(s.options.width) / static_cast<float>(s.options.height);
    const Camera camera = with_lens(s.scene.select_camera(s.options.camera, aspect), s.options.settings);
    const budget::Traced t = budget::trace_within(s.scene, shaders, camera, s.options.width, s.options.height, req.budget);
    const double target = budget::kTraceNoiseShare * req.budget;
    log::info("traced --raytrace path: " + std::to_string(t.spp) + " spp in " + format_number("%.1f", t.ms) + " ms, noise estimate " +
              format_number("%.4f", t.noise) +
              (t.within ? " (target " + format_number("%.4f", target) + ")"
                        : " above the target " + format_number("%.4f", target) + " at the sample limit: the budget is not promised"));
    if (!t.within && !p.flags.count("--quiet"))
        std::fprintf(stderr, "error budget: the tracer stopped at %d spp with a noise estimate of %.4f, above its target %.4f\n", t.spp, t.noise,
                     target);
    if (t.nonfinite_samples) log::warn(std::to_string(t.nonfinite_samples) + " non-finite samples were replaced by 0");
    write_image(out_path, t.image, exposure);
    if (verify) {
        const budget::Reference ref = verify_reference(p, s, shaders);
        print_achieved(budget::block_error(t.image, ref.image), req.budget, target, ref);
    }
    if (p.has("--stats")) {  // the traced frame has no passes: what the tracer did
        nlohmann::json j;
        j["scene"] = p.positional[0];
        j["width"] = s.options.width;
        j["height"] = s.options.height;
        j["error_budget"] = {{"budget", req.budget}, {"traced", true}, {"spp", t.spp}, {"trace_ms", t.ms}, {"noise", t.noise},
                             {"within_target", t.within}};
        write_json(p.get("--stats"), j);
    }
    return check_gl_errors(s);
}

// Whether `out` holds exactly one printf integer conversion (%d, %4d, %04d) and no other '%'.
bool has_frame_pattern(const std::string& out) {
    const size_t at = out.find('%');
    if (at == std::string::npos) return false;
    size_t i = at + 1;
    while (i < out.size() && i - at <= 3 && std::isdigit(static_cast<unsigned char>(out[i]))) ++i;
    if (i >= out.size() || out[i] != 'd') throw bad_input(out + ": the frame pattern must be %d, %4d or %04d (at most 2 digits)");
    if (out.find('%', i) != std::string::npos) throw bad_input(out + ": only one '%' frame pattern is allowed");
    return true;
}

fs::path frame_path(const std::string& pattern, int frame) {
    char buf[4096];
    std::snprintf(buf, sizeof buf, pattern.c_str(), frame);
    return fs::path(buf);
}

// The frame times of a render: --time T is one frame; --time A:B every 1/fps from A up to B.
std::vector<float> frame_times(const SceneSetup& s, float fps) {
    std::vector<float> times{s.time_first};
    const double span = static_cast<double>(s.time_last) - s.time_first;
    const long frames = static_cast<long>(std::floor(span * fps + 1e-4)) + 1;
    if (frames > 100000) throw bad_input("--time A:B at --fps " + format_number("%g", fps) + " is " + std::to_string(frames) + " frames (at most 100000)");
    for (long i = 1; i < frames; ++i) times.push_back(static_cast<float>(s.time_first + static_cast<double>(i) / fps));
    return times;
}

}  // namespace

int cmd_render(const Args& args) { return run_render(args, nullptr); }

int run_render(const Args& args, BatchSession* batch) {
    std::vector<std::string> with_value = kSceneSetupOptions;
    with_value.insert(with_value.end(), {"-o", "--output", "--exposure", "--stats", "--raytrace", "--spp", "--max-depth",
                                         "--seed", "--spp-shard", "--time-limit", "--fps"});
    with_value.insert(with_value.end(), kBudgetOptions.begin(), kBudgetOptions.end());
    std::vector<std::string> flags = kSceneSetupFlags;
    flags.insert(flags.end(), {"--timings", "--verify"});
    const Parsed p = parse(args, with_value, flags);
    // --error-budget E: bad input is found before any GL work.
    const std::optional<BudgetRequest> budget_req = budget_request(p);
    const bool verify = p.flags.count("--verify") > 0;
    if (verify && !budget_req) throw bad_input("--verify goes with --error-budget E (it renders the path reference and prints the achieved error)");
    if (budget_req && p.has("--raytrace")) throw bad_input("--error-budget chooses raster settings: it does not go with --raytrace");
    if (budget_req && p.has("--time") && p.get("--time").find(':') != std::string::npos)
        throw bad_input("--error-budget renders one still: it does not go with --time A:B");
    if (p.positional.size() != 1) throw bad_input("render needs exactly one SCENE (got " + std::to_string(p.positional.size()) + ")");
    std::string out = p.has("-o") ? p.get("-o") : p.has("--output") ? p.get("--output") : "";
    if (out.empty()) throw bad_input("render needs -o OUT.png or -o OUT.exr");
    const fs::path out_path(out);
    {
        std::string e = out_path.extension().string();
        for (auto& c : e) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
        if (e != ".png" && e != ".exr") throw bad_input(out + ": the output must be .png or .exr");
        if (e == ".exr" && !image_io_built())
            throw bad_input(out + ": writing .exr needs OpenImageIO, which this candela was built without "
                                  "(install libopenimageio-dev, e.g. bash .ci/setup, then configure and build again)");
    }
    const float exposure = p.has("--exposure") ? parse_float("--exposure", p.get("--exposure"), -32, 32) : 0.0f;
    // Fail before rendering, not after: the output's directory must exist.
    {
        const fs::path dir = out_path.has_parent_path() ? out_path.parent_path() : fs::path(".");
        if (!fs::is_directory(dir)) throw bad_input(out + ": cannot write: no directory " + dir.string());
        if (access(dir.c_str(), W_OK) != 0) throw bad_input(out + ": cannot write: " + dir.string() + " is not writable");
    }
    SceneSetup s = setup_scene(p, p.positional[0], 512, 512);
    // Sequences: --time A:B --fps F writes frames at A, A + 1/F, ... <= B to a path with
    // one printf integer conversion (out_%04d.png: the frame index from 0).
    if (p.has("--fps")) s.options.settings.camera.fps = parse_float("--fps", p.get("--fps"), 1.0f, 1000.0f);
    const float fps = s.options.settings.camera.fps;
    const bool sequence = s.time_last > s.time_first;
    if (sequence && !has_frame_pattern(out))
        throw bad_input(out + ": --time A:B writes a sequence: the output needs a frame-number pattern such as out_%04d.png");
    if (!sequence && has_frame_pattern(out)) throw bad_input(out + ": a frame-number pattern needs --time A:B (a sequence)");
    // A .png gets its display transform on the GPU (the tonemap pass); an .exr is the HDR target.
    const bool display = is_display_format(out_path);
    s.options.output = display ? FrameOutput::display : FrameOutput::hdr;
    s.options.exposure_ev = exposure;

    auto t0 = std::chrono::steady_clock::now();
    ContextResult ctx;
    if (batch) {  // `candela batch`: the batch's context and programs
        if (s.backend != Backend::auto_select && s.backend != batch->context->backend())
            throw bad_input(std::string("--backend ") + to_string(s.backend) + ": the batch renders with " +
                            to_string(batch->context->backend()) + " (one context per batch: give --backend to 'candela batch')");
        s.debug = batch->debug;
    } else {
        ctx = open_context(s);
        if (!ctx.context) return static_cast<int>(ExitCode::no_gl);
    }
    const Context& context = batch ? *batch->context : *ctx.context;
    // Texture mipmaps on a second context beside the main thread (GpuScene); the same images.
    // CANDELA_MIP_WORKER=0 makes them on the main thread (to compare). Destroyed before ctx.
    std::unique_ptr<GlWorker> mip_worker;
    if (!batch && mip_worker_wanted()) {
        mip_worker = std::make_unique<GlWorker>(ctx.context->create_shared());
        s.options.mip_worker = mip_worker.get();
    }
    const double context_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();

    const ShaderLibrary own_shaders(s.shader_dir);
    BatchSession::Programs* shared = batch && batch->share_programs ? &batch->programs_for(s.shader_dir) : nullptr;
    const ShaderLibrary& shaders = shared ? *shared->shaders : own_shaders;
    s.options.programs = shared ? shared->cache.get() : nullptr;
    finish_lighting(s, shaders);
    const std::vector<float> times = frame_times(s, fps);
    std::optional<budget::Choice> choice;
    if (budget_req) {
        std::string text;
        choice = choose_for_scene(*budget_req, s.scene, shaders, s.options.camera, s.options.width, s.options.height, false, text);
        if (!p.flags.count("--quiet")) std::fprintf(stderr, "%s", text.c_str());
        const DebugView view = s.options.settings.debug.view;
        s.options.settings = budget_settings(*choice, p);
        s.options.settings.debug.view = view;
    }
    if (p.has("--raytrace")) {
        for (size_t i = 0; i < times.size(); ++i) {
            if (i > 0) {
                s.options.time = times[i];
                pose_scene(s.scene, s.options.animation, times[i]);
            }
            const int rc = raytrace(p, s, sequence ? frame_path(out, static_cast<int>(i)) : out_path, exposure);
            if (rc != 0) return rc;
        }
        return 0;
    }
    if (sequence) {
        // One loop for the whole sequence: the context, programs and textures are reused.
        FrameLoop loop(s.scene, shaders, s.options);
        for (size_t i = 0; i < times.size(); ++i) {
            if (i > 0) loop.set_pose(s.scene, s.options.animation, times[i]);
            if (i == 0) loop.warmup(s.options.warmup);
            loop.measure_frame();
            const StillResult r = loop.finish();
            const fs::path path = frame_path(out, static_cast<int>(i));
            if (const std::size_t bad = count_nonfinite(r.radiance))
                log::warn(path.string() + ": " + std::to_string(bad) + " non-finite values in the rendered radiance (written as 0 in .png)");
            if (display) write_display_rgba8(path, r.display, r.radiance.width, r.radiance.height);
            else write_image(path, r.radiance, exposure);
        }
        log::info("wrote " + std::to_string(times.size()) + " frames, " + format_number("%.3f", times.front()) + " to " +
                  format_number("%.3f", times.back()) + " s at " + format_number("%g", fps) + " fps");
        return check_gl_errors(s);
    }
    if (choice && choice->trace) return render_traced(p, s, shaders, *budget_req, out_path, exposure, verify);
    const StillResult result = render_still(s.scene, shaders, s.options);
    warn_idle_knobs(p, result.features);
    const std::size_t bad = count_nonfinite(result.radiance);
    if (bad) log::warn(out + ": " + std::to_string(bad) + " non-finite values in the rendered radiance (written as 0 in .png)");
    t0 = std::chrono::steady_clock::now();
    if (display) write_display_rgba8(out_path, result.display, result.radiance.width, result.radiance.height);
    else write_image(out_path, result.radiance, exposure);
    const double write_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    if (verify) {
        // The promise checked: the tracer's reference of this view, and the block error against it.
        const budget::Reference ref = verify_reference(p, s, shaders);
        print_achieved(budget::block_error(result.radiance, ref.image), budget_req->budget,
                       choice->predictions[static_cast<size_t>(choice->chosen)].error, ref);
    }
    if (p.has("--stats")) {
        nlohmann::json j = stats_json({context.device_string(), to_string(context.backend()), p.positional[0]},
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

}  // namespace candela::cli
