// `candela bench`: frame (median frame time of effect or render-path variants), rays (ray-tracer
// ray rates), reload (shader save to new frame) and accuracy (the accuracy engine,
// engine/accuracy/, through accuracy.hpp).
#include "commands.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include <unistd.h>

#include <nlohmann/json.hpp>

#include "accuracy.hpp"
#include "core/error.hpp"
#include "core/log.hpp"
#include "options.hpp"
#include "budget.hpp"
#include "rt/rt_scene.hpp"
#include "scene/animation.hpp"
#include "render/stats.hpp"
#include "render/renderer.hpp"
#include "render/settings.hpp"
#include "render/still.hpp"
#include "rt/ray_rates.hpp"
#include "rt/ray_tracer.hpp"
#include "image/image.hpp"
#include "shader/file_watcher.hpp"

namespace candela::cli {
namespace fs = std::filesystem;

namespace {

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
    s.backend = backend_option(p, false);
    ContextResult ctx = open_context(s);
    if (!ctx.context) return static_cast<int>(ExitCode::no_gl);
    const ShaderLibrary shaders(s.shader_dir);
    std::printf("device: %s (%s); %dx%d, %d spp per mode, medians of %d runs after one warm-up sample\n",
                ctx.context->device_string().c_str(), to_string(ctx.context->backend()), w, h, spp, repeats);
    std::printf("%-28s %10s %10s %10s %12s %12s %12s %10s %10s %6s\n", "scene", "triangles", "bvh ms", "SAH", "primary Mr/s",
                "AO Mr/s", "bounce Mr/s", "nodes/ray", "prims/ray", "lanes");
    for (const std::string& name : p.positional) {
        const Scene scene = load_scene(name, false);
        GpuScene gpu(scene);
        const Camera camera = scene.select_camera("", static_cast<float>(w) / static_cast<float>(h));
        const rt::RayRates r = rt::measure_ray_rates(shaders, scene, gpu, camera, w, h, spp, repeats);
        std::printf("%-28s %10zu %10.1f %10.2f %12.2f %12.2f %12.2f %10.1f %10.1f %5.0f%%\n",
                    name.substr(name.size() > 28 ? name.size() - 28 : 0).c_str(), r.triangles, r.bvh.build_ms, r.bvh.sah_cost,
                    r.primary_mrays, r.ao_mrays, r.bounce_mrays, r.nodes_per_ray, r.primitives_per_ray, 100.0 * r.lane_utilisation);
    }
    return 0;
}

// The time from a shader file's save to the first frame drawn with the rebuilt program: a copy
// of the shaders is edited (a comment appended to lighting/shading.glsl, which the shading
// programs include) and the watcher, the reload and one frame run as in the viewer.
int bench_reload(const Args& args) {
    std::vector<std::string> with_value = kSceneSetupOptions;
    with_value.push_back("--count");
    const Parsed p = parse(args, with_value, kSceneSetupFlags);
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
    finish_lighting(s, shaders);
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

// `candela bench accuracy [SCENE...] -o DIR`: accuracy_options() and run_accuracy() (accuracy.hpp).
// Hidden options (not in the usage text; `candela farm` calls the same functions): the steps of a
// run split into one process per section, all given the same SCENE..., --effect and --quick:
//   --list-sections                 the sections' labels, one a line, in index order
//   --section K --section-dir DIR   runs section K alone into DIR (skips it if DIR already holds it)
//   --assemble DIR (once per section, in index order) -o OUT   the outputs from the saved sections
int bench_accuracy(const Args& args) {
    const Parsed p = parse(args, {"-o", "--report", "--shader-dir", "--backend", "--effect", "--section", "--section-dir", "--assemble"},
                           {"--quick", "--quiet", "--list-sections"});
    const bool list = p.flags.count("--list-sections") > 0, section = p.has("--section"), assemble = p.has("--assemble");
    if (list + section + assemble > 1) throw bad_input("bench accuracy: --list-sections, --section and --assemble go alone");
    if (section != p.has("--section-dir")) throw bad_input("bench accuracy: --section K goes with --section-dir DIR");
    if (!p.has("-o") && !list && !section) throw bad_input("bench accuracy needs -o DIR");
    const accuracy::Options o = accuracy_options(p, args, "candela bench accuracy");
    if (list) {
        for (const accuracy::Task& t : accuracy::plan(o)) std::printf("%s\n", t.label.c_str());
        return 0;
    }
    if (section) return run_accuracy_section(o, parse_int("--section", p.get("--section"), 0, 1000000), p.get("--section-dir"));
    if (assemble) {
        const std::vector<std::string> dirs = p.all("--assemble");
        return assemble_accuracy(o, std::vector<fs::path>(dirs.begin(), dirs.end()));
    }
    return run_accuracy(o);
}

constexpr const char* kSpeedOfLight = "speed-of-light";

// `candela bench frame SCENE`: the variants (--effects values, or --path values) and the
// speed-of-light frame rendered interleaved, frame by frame.
int bench_frame(const Args& args) {
    std::vector<std::string> with_value = kSceneSetupOptions;
    with_value.push_back("--json");
    with_value.insert(with_value.end(), kBudgetOptions.begin(), kBudgetOptions.end());
    const Parsed p = parse(args, with_value, kSceneSetupFlags);
    if (p.positional.size() != 1) throw bad_input("bench frame needs exactly one SCENE");
    // --error-budget E: the variants are the budget's choice and the default settings.
    const std::optional<BudgetRequest> budget_req = budget_request(p);
    if (budget_req && p.all("--path").size() > 1) throw bad_input("bench frame: --error-budget takes at most one --path");
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
    finish_lighting(s, shaders);
    std::vector<StillOptions> options(variants.size(), s.options);
    if (budget_req) {
        std::string text;
        const budget::Choice choice = choose_for_scene(*budget_req, s.scene, shaders, s.options.camera, s.options.width,
                                                       s.options.height, false, text);
        std::printf("%s", text.c_str());
        if (choice.trace)
            std::printf("bench frame times raster frames: the most accurate raster candidate stands in for the tracer (render --error-budget traces)\n");
        const std::string& name = budget::ladder()[static_cast<size_t>(choice.predictions[static_cast<size_t>(choice.chosen)].candidate)].name;
        variants = {"budget:" + name, "all"};
        options.assign(2, s.options);
        options[0].settings = budget_settings(choice, p);
    }
    std::vector<std::unique_ptr<FrameLoop>> loops;
    for (size_t v = 0; v < variants.size(); ++v) {
        if (budget_req && v == 0) {  // the budget's settings, made above
            loops.push_back(std::make_unique<FrameLoop>(s.scene, shaders, options[v]));
            continue;
        }
        const size_t space = variants[v].find(" --path ");
        apply_effects(options[v].settings, variants[v].substr(0, space));
        if (space != std::string::npos) apply_knob(options[v].settings, "render.path=" + variants[v].substr(space + 8));
        apply_knobs(options[v].settings, p.all("--set"));
        loops.push_back(std::make_unique<FrameLoop>(s.scene, shaders, options[v]));
    }
    // The speed-of-light frame: the cheapest correct image of the same scene at the same size, a
    // depth prepass and one forward pass with the scene's own lights, no effect (so no shadows).
    // Every variant's time is also printed as a ratio to it: ratios carry from one machine to
    // another where absolute times do not.
    variants.push_back(kSpeedOfLight);
    options.push_back(s.options);
    apply_effects(options.back().settings, "none");
    apply_knob(options.back().settings, "render.path=forward");
    apply_knob(options.back().settings, "forward.depth_prepass=1");
    loops.push_back(std::make_unique<FrameLoop>(s.scene, shaders, options.back()));
    for (auto& loop : loops) loop->warmup(s.options.warmup);
    for (int f = 0; f < s.options.frames; ++f)
        for (auto& loop : loops) loop->measure_frame();
    std::vector<StillResult> results;
    for (auto& loop : loops) results.push_back(loop->finish());
    std::printf("device: %s (%s)\nscene: %s at %dx%d, %d frames per variant after %d warm-up\n",
                ctx.context->device_string().c_str(), to_string(ctx.context->backend()), p.positional[0].c_str(),
                s.options.width, s.options.height, s.options.frames, s.options.warmup);
    nlohmann::json all = nlohmann::json::array();
    const double light_ms = results.back().median_frame_ms();
    for (size_t v = 0; v < variants.size(); ++v) {
        const auto [q1, q3] = quartiles(results[v].frame_ms);
        const std::string label =
            variants[v] == kSpeedOfLight || variants[v].rfind("budget:", 0) == 0 ? variants[v] : "effects=" + variants[v];
        std::printf("%-20s frame median %8.2f ms  IQR [%.2f, %.2f]  x%.2f speed of light  graph %.3f ms  passes:", label.c_str(),
                    results[v].median_frame_ms(), q1, q3, results[v].median_frame_ms() / light_ms, results[v].report.graph_ms);
        for (const auto& ps : results[v].report.passes) std::printf(" %s %.2f", ps.name.c_str(), ps.gpu_ms);
        std::printf(" (GPU ms, median)\n");
        nlohmann::json j = stats_json({ctx.context->device_string(), to_string(ctx.context->backend()), p.positional[0]},
                                      options[v], results[v]);
        j["variant"] = variants[v];
        j["speed_of_light_ratio"] = results[v].median_frame_ms() / light_ms;
        all.push_back(std::move(j));
    }
    if (variants.size() >= 3)  // two measured variants and the speed-of-light frame
        std::printf("ratio %s / %s = %.3f\n", variants[0].c_str(), variants[1].c_str(),
                    results[0].median_frame_ms() / results[1].median_frame_ms());
    if (p.has("--json")) write_json(p.get("--json"), all);
    return check_gl_errors(s);
}

// `candela bench animation SCENE...`: what animation costs per frame: posing on the CPU
// (evaluate: channels, world matrices, morphing and skinning; apply: into the scene), the upload of
// the posed vertices, one raster frame at the new pose, and the tracer's geometry update by a full
// BVH rebuild and by a refit. Medians over --poses poses spread over the animation (--animation, else 0).
int bench_animation(const Args& args) {
    std::vector<std::string> with_value = kSceneSetupOptions;
    with_value.push_back("--poses");
    const Parsed p = parse(args, with_value, kSceneSetupFlags);
    if (p.positional.empty()) throw bad_input("bench animation needs at least one SCENE with an animation");
    const int poses = p.has("--poses") ? parse_int("--poses", p.get("--poses"), 2, 1000) : 8;
    SceneSetup s0 = setup_scene(p, p.positional[0], 1280, 720);
    ContextResult ctx = open_context(s0);
    if (!ctx.context) return static_cast<int>(ExitCode::no_gl);
    const ShaderLibrary shaders(s0.shader_dir);
    std::printf("device: %s (%s); %dx%d, medians over %d poses of animation %s\n", ctx.context->device_string().c_str(),
                to_string(ctx.context->backend()), s0.options.width, s0.options.height, poses,
                p.has("--animation") ? p.get("--animation").c_str() : "0");
    std::printf("%-28s %10s %10s %10s %10s %10s %10s %10s %10s\n", "scene", "triangles", "pose ms", "apply ms", "upload ms",
                "raster ms", "rebuild ms", "refit ms", "static ms");
    for (size_t si = 0; si < p.positional.size(); ++si) {
        SceneSetup s = si == 0 ? std::move(s0) : setup_scene(p, p.positional[si], 1280, 720);
        finish_lighting(s, shaders);
        Scene& scene = s.scene;
        if (scene.animations.empty()) throw bad_input(p.positional[si] + ": bench animation needs a scene with an animation");
        const int animation = std::max(0, s.options.animation);
        const Animation& a = scene.animations[static_cast<size_t>(animation)];
        GpuScene gpu(scene);
        Renderer renderer(shaders, scene, gpu, s.options.settings);
        const Camera camera = scene.select_camera(s.options.camera, static_cast<float>(s.options.width) / static_cast<float>(s.options.height));
        rt::RtScene rt_scene(scene, static_cast<int>(scene.materials.size()));
        auto now = [] { return std::chrono::steady_clock::now(); };
        auto ms = [](auto t0, auto t1) { return std::chrono::duration<double, std::milli>(t1 - t0).count(); };
        renderer.render(camera, s.options.width, s.options.height);  // compiles and captures once
        glFinish();
        std::vector<double> eval, apply, upload, raster, rebuild, refit, still;
        for (int i = 0; i < poses; ++i) {
            const float t = a.start + (a.end - a.start) * (static_cast<float>(i) + 0.5f) / static_cast<float>(poses);
            auto t0 = now();
            Pose pose = evaluate_pose(scene, animation, t);
            auto t1 = now();
            apply_pose(scene, std::move(pose));
            auto t2 = now();
            gpu.update_pose();
            glFinish();
            auto t3 = now();
            renderer.render(camera, s.options.width, s.options.height);
            glFinish();
            auto t4 = now();
            renderer.render(camera, s.options.width, s.options.height);  // the same pose again: what a still frame costs
            glFinish();
            auto t5 = now();
            eval.push_back(ms(t0, t1)), apply.push_back(ms(t1, t2)), upload.push_back(ms(t2, t3)), raster.push_back(ms(t3, t4));
            still.push_back(ms(t4, t5));
            rebuild.push_back(rt_scene.update(scene, rt::RtUpdate::rebuild).total_ms());
            refit.push_back(rt_scene.update(scene, rt::RtUpdate::refit).total_ms());
        }
        std::printf("%-28s %10zu %10.2f %10.2f %10.2f %10.2f %10.2f %10.2f %10.2f\n",
                    p.positional[si].substr(p.positional[si].size() > 28 ? p.positional[si].size() - 28 : 0).c_str(), scene.triangle_count(),
                    median(eval), median(apply), median(upload), median(raster), median(rebuild), median(refit), median(still));
    }
    return 0;
}


// `candela bench lights`: the cost of lights against the number of lights, with the raster's
// error against the tracer at each count: generated:lights-bounded:N (each point of the floor
// reached by about one light at any N), generated:street:N (lamps without a range,
// lights.cutoff) or generated:emitters:N (small emitters in the lights' places). For each N: the default frame's and the speed-of-light frame's median times,
// and the block error (block_agreement, 4x4, display values) of the default frame's radiance
// against `--raytrace path` at the same size and --spp samples, then the same error with the
// reference's noise taken out (block_bias: RMS over blocks, from two independent halves of the
// reference) and the reference's own noise (RMS).
int bench_lights(const Args& args) {
    std::vector<std::string> with_value = kSceneSetupOptions;
    with_value.insert(with_value.end(), {"--counts", "--scene", "--spp"});
    const Parsed p = parse(args, with_value, kSceneSetupFlags);
    if (!p.positional.empty()) throw bad_input("bench lights takes no SCENE: --scene bounded|street|emitters chooses the generator");
    const std::string which = p.has("--scene") ? p.get("--scene") : "bounded";
    if (which != "bounded" && which != "street" && which != "emitters")
        throw bad_input("bench lights: --scene must be bounded, street or emitters, not '" + which + "'");
    std::vector<int> counts;
    {
        // (More than 64 emissive polygons are shaded by the pieces, not by LTC: area_lights.cpp.)
        const std::string list = p.has("--counts") ? p.get("--counts") : which == "emitters" ? "4,16,64" : "4,16,64,256";
        size_t start = 0;
        while (start <= list.size()) {
            const size_t comma = std::min(list.find(',', start), list.size());
            counts.push_back(parse_int("--counts", list.substr(start, comma - start), 1, 100000));
            start = comma + 1;
        }
    }
    const int spp = p.has("--spp") ? parse_int("--spp", p.get("--spp"), 1, 1 << 16) : 32;
    const std::string prefix = which == "bounded" ? "generated:lights-bounded:" : which == "street" ? "generated:street:" : "generated:emitters:";
    std::unique_ptr<Context> context;
    for (const int n : counts) {
        SceneSetup s = setup_scene(p, prefix + std::to_string(n), 320, 180);
        if (!p.has("--frames")) s.options.frames = 3;
        if (!p.has("--warmup")) s.options.warmup = 1;
        if (!context) {
            ContextResult ctx = open_context(s);
            if (!ctx.context) return static_cast<int>(ExitCode::no_gl);
            context = std::move(ctx.context);
            std::printf("device: %s (%s); %dx%d, %d frames after %d warm-up, reference %d spp\n", context->device_string().c_str(),
                        to_string(context->backend()), s.options.width, s.options.height, s.options.frames, s.options.warmup, spp);
            std::printf("%-30s %8s %12s %12s %14s %12s %12s %12s %10s\n", "scene", "lights", "default ms", "light ms", "block error",
                        "bias rms", "ref noise", "luminance", "trace ms");
        }
        const ShaderLibrary shaders(s.shader_dir);
        finish_lighting(s, shaders);
        StillOptions fast = s.options;
        apply_effects(fast.settings, "none");
        apply_knob(fast.settings, "render.path=forward");
        apply_knob(fast.settings, "forward.depth_prepass=1");
        apply_knobs(s.options.settings, p.all("--set"));
        FrameLoop full(s.scene, shaders, s.options), light(s.scene, shaders, fast);
        full.warmup(s.options.warmup);
        light.warmup(s.options.warmup);
        for (int f = 0; f < s.options.frames; ++f) full.measure_frame(), light.measure_frame();
        const StillResult a = full.finish(), b = light.finish();
        // The reference in two independent halves (seeds 1 and 2), so that its noise can be taken
        // out of the error (block_bias); their mean is the --spp reference.
        GpuScene gpu(s.scene);
        const float aspect = static_cast<float>(s.options.width) / static_cast<float>(s.options.height);
        ImageF halves[2];
        double trace_ms = 0;
        for (int h = 0; h < 2; ++h) {
            rt::Options o;
            o.mode = rt::Mode::path;
            o.spp = std::max(spp / 2, 1);
            o.seed = static_cast<std::uint32_t>(h + 1);
            rt::RayTracer tracer(shaders, s.scene, gpu, o);
            rt::Result r = tracer.render(s.scene.select_camera(s.options.camera, aspect), s.options.width, s.options.height);
            halves[h] = std::move(r.image);
            trace_ms += r.trace_ms;
        }
        ImageF reference = halves[0];
        for (size_t i = 0; i < reference.pixels.size(); ++i) reference.pixels[i] = 0.5f * (halves[0].pixels[i] + halves[1].pixels[i]);
        const BlockAgreement e = block_agreement(a.radiance, reference, 4);
        const BlockBias bias = block_bias(a.radiance, halves[0], halves[1], 4);
        std::printf("%-30s %8d %12.2f %12.2f %14.5f %12.5f %12.5f %12.4f %10.0f\n", (prefix + std::to_string(n)).c_str(), n,
                    a.median_frame_ms(), b.median_frame_ms(), e.mean_abs, bias.rms, bias.ref_noise_rms, e.luminance_ratio, trace_ms);
        if (count_nonfinite(a.radiance) != 0 || count_nonfinite(reference) != 0) throw Error(ExitCode::internal, prefix + std::to_string(n) + ": non-finite pixels");
    }
    return 0;
}

}  // namespace

int cmd_bench(const Args& args) {
    const std::string which = args.empty() ? "" : args[0];
    const Args rest = args.empty() ? Args{} : Args(args.begin() + 1, args.end());
    if (which == "frame") return bench_frame(rest);
    if (which == "rays") return bench_rays(rest);
    if (which == "reload") return bench_reload(rest);
    if (which == "accuracy") return bench_accuracy(rest);
    if (which == "animation") return bench_animation(rest);
    if (which == "lights") return bench_lights(rest);
    if (which == "error-budget") return bench_error_budget(rest);
    throw bad_input("bench needs a benchmark: 'candela bench frame SCENE' or 'candela bench rays SCENE...'");
}

}  // namespace candela::cli
