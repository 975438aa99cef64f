#include "accuracy/run.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <memory>

#include "accuracy/error_budget_measure.hpp"
#include "accuracy/metrics.hpp"
#include "accuracy/plan.hpp"
#include "core/error.hpp"
#include "render/renderer.hpp"
#include "render/still.hpp"
#include "rt/ray_tracer.hpp"
#include "rt/tracer_options.hpp"
#include "scene/animation.hpp"

namespace candela::accuracy {

namespace {

std::string join(const std::vector<std::string>& v, const char* sep) {
    std::string s;
    for (const auto& x : v) s += (s.empty() ? "" : sep) + x;
    return s;
}

// The time a sweep's scene is shown at, and its shutter. Animated scenes (motion blur) are posed
// at a fixed time: animation 0 at its midpoint, (start + end) / 2; the shutter (camera.shutter of
// the sweep's first variant, at camera.fps) is centred on it. The raster frame is the pose at that
// time with GpuScene::set_motion of the poses at open and close; the tracer poses the scene at
// its samples' times in the shutter (rt::Options::pose_at).
struct SceneTime {
    Scene* scene = nullptr;
    int animation = -1;  // -1: not animated
    float time = 0.0f;
    ShutterInterval shutter;
    bool moving() const { return scene && animation >= 0 && !shutter.instant(); }
};

SceneTime pose_for_sweep(Scene& scene, const RenderSettings& s) {
    SceneTime t;
    t.scene = &scene;
    if (scene.animations.empty()) return t;
    t.animation = 0;
    const Animation& a = scene.animations.front();
    t.time = 0.5f * (a.start + a.end);
    t.shutter = shutter_interval(t.time, s.camera.shutter, s.camera.fps);
    pose_scene(scene, t.animation, t.time);
    return t;
}

// The raster side: the poses at shutter open and close (the frame's pose is the scene's own).
void set_sweep_motion(GpuScene& gpu, const SceneTime& t) {
    if (t.moving()) gpu.set_motion(evaluate_pose(*t.scene, t.animation, t.shutter.open), evaluate_pose(*t.scene, t.animation, t.shutter.close));
}

rt::Result trace(const Run& c, const Scene& scene, GpuScene& gpu, const AccuracySweep::Reference& r, int spp, std::uint32_t seed,
                 const RenderSettings& settings, const SceneTime* motion = nullptr) {
    rt::Options o = rt::tracer_options(settings);
    if (motion && motion->moving()) {
        // The exact motion blur: each time slice of the shutter poses the scene (the tracer leaves
        // it at the shutter's centre, the sweep's time, when it is done).
        const SceneTime m = *motion;
        o.pose_at = [m](float u) { pose_scene(*m.scene, m.animation, m.shutter.open + u * (m.shutter.close - m.shutter.open)); };
    }
    o.mode = r.mode;
    o.spp = spp;
    o.max_depth = r.max_depth;
    o.jitter = r.jitter;
    o.seed = seed;
    o.indirect_occlusion = r.indirect_occlusion;
    o.visibility_light = 0;  // the references are radiance, whatever debug.light says
    rt::RayTracer tracer(c.shaders, scene, gpu, o);
    // The variant's lens (camera.aperture / camera.focus_distance) over the camera's own, as the
    // raster renderer applies it.
    const Camera camera = with_lens(scene.select_camera("", static_cast<float>(c.width) / static_cast<float>(c.height)), settings);
    return tracer.render(camera, c.width, c.height);
}

// The reference of a sweep (metrics.hpp): the tracer at two seeds, their mean and its noise.
Reference make_reference(const Run& c, const Scene& scene, GpuScene& gpu, const AccuracySweep::Reference& r, const RenderSettings& s,
                         const SceneTime* motion = nullptr) {
    const rt::Result a = trace(c, scene, gpu, r, r.spp, 1, s, motion);
    const rt::Result b = trace(c, scene, gpu, r, r.spp, 2, s, motion);
    if (count_nonfinite(a.image) || count_nonfinite(b.image) || a.nonfinite_samples || b.nonfinite_samples)
        throw Error(ExitCode::internal, std::string("accuracy: non-finite values in a ") + rt::to_string(r.mode) + " reference");
    Reference ref;
    ref.image = a.image;
    for (size_t i = 0; i < ref.image.pixels.size(); ++i) ref.image.pixels[i] = 0.5f * (a.image.pixels[i] + b.image.pixels[i]);
    ref.noise = compare(a.image, b.image, 2.0 / 255.0).rmse / 2.0;
    ref.half_diff = a.image;
    for (size_t i = 0; i < ref.half_diff.pixels.size(); ++i) ref.half_diff.pixels[i] = 0.5f * (a.image.pixels[i] - b.image.pixels[i]);
    ref.ms = a.trace_ms + b.trace_ms;
    ref.spp = 2 * r.spp;
    return ref;
}

RenderSettings variant_settings(const AccuracySweep& s, const AccuracySweep::Variant& v) {
    RenderSettings rs;
    apply_effects(rs, v.effects);
    apply_knobs(rs, v.knobs);
    if (s.buffer == Buffer::visibility) rs.debug.view = DebugView::visibility, rs.debug.light = 0;
    if (s.buffer == Buffer::ao) rs.debug.view = DebugView::ao;
    if (s.buffer == Buffer::indirect) rs.debug.view = DebugView::indirect;
    return rs;
}

// Times and images of the raster variants of one sweep on one scene (one renderer, so shader
// compilation is paid once per program).
void raster_rows(const Run& c, const AccuracySweep& s, const Scene& scene, GpuScene& gpu, std::vector<Row>& rows) {
    std::unique_ptr<Renderer> renderer;
    const Camera camera = scene.select_camera("", static_cast<float>(c.width) / static_cast<float>(c.height));
    for (const AccuracySweep::Variant& v : s.variants) {
        const RenderSettings rs = variant_settings(s, v);
        if (!renderer) {
            renderer = std::make_unique<Renderer>(c.shaders, scene, gpu, rs);
            renderer->set_synchronous_timing(true);
        } else {
            renderer->set_settings(rs);
        }
        for (int i = 0; i < c.warmup; ++i) renderer->render(camera, c.width, c.height);
        glFinish();
        std::vector<double> own, frame;
        for (int i = 0; i < c.frames; ++i) {
            const auto t0 = Clock::now();
            renderer->render(camera, c.width, c.height);
            glFinish();
            frame.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
            renderer->resolve_gpu_times();
            double sum = 0.0;
            bool valid = true;
            for (const PassStats& p : renderer->last_frame().passes) {
                const bool mine = s.own_passes.empty() || std::find(s.own_passes.begin(), s.own_passes.end(), p.name) != s.own_passes.end();
                if (!mine) continue;
                if (p.sync_ms < 0.0) valid = false;
                sum += p.sync_ms;
            }
            if (valid) own.push_back(sum);
        }
        Row row;
        row.effect = s.effect;
        row.variant = v.name;
        row.settings = "--effects " + v.effects + (v.knobs.empty() ? "" : " --set " + join(v.knobs, " --set "));
        row.scene = s.scene;
        row.width = c.width;
        row.height = c.height;
        if (!own.empty()) {
            row.ms = median(own);
            const auto [q1, q3] = quartiles(own);
            row.iqr = q3 - q1;
        }
        row.frame_ms = median(frame);
        row.image = renderer->read_radiance();
        if (count_nonfinite(row.image)) throw Error(ExitCode::internal, s.effect + " " + v.name + ": non-finite values in the raster image");
        rows.push_back(std::move(row));
        c.progress.step(s.effect + ": " + v.name);
    }
}

// Variants whose --effects is "budget:E" stand for --error-budget E's choice on this scene and view
// (error_budget.hpp): resolved here, where the tracer can measure the view's statistics. The
// row's name says which candidate it became. A choice of the tracer rung leaves the raster
// variants and comes back as (variant name, E): traced_budget_rows makes its rows.
std::vector<std::pair<std::string, double>> resolve_budget_variants(const Run& c, AccuracySweep& s, const Scene& scene) {
    std::optional<budget::SceneStats> stats;
    std::vector<std::pair<std::string, double>> traced;
    const float aspect = static_cast<float>(c.width) / static_cast<float>(c.height);
    std::vector<AccuracySweep::Variant> raster;
    for (AccuracySweep::Variant v : s.variants) {
        if (v.effects.rfind("budget:", 0) == 0) {
            if (!stats) stats = budget::scene_stats(scene, c.shaders, with_lens(scene.select_camera("", aspect), RenderSettings{}), aspect);
            const double e = std::stod(v.effects.substr(7));
            const budget::Choice choice = budget::choose(budget::predict(budget::builtin_model(), *stats), e);
            if (choice.trace) {
                traced.emplace_back(v.name + " -> trace", e);
                continue;
            }
            const budget::Candidate& chosen = budget::ladder()[static_cast<size_t>(choice.predictions[static_cast<size_t>(choice.chosen)].candidate)];
            v.name += " -> " + chosen.name;
            v.effects = chosen.effects;
            v.knobs = chosen.knobs;
        }
        raster.push_back(v);
    }
    s.variants = raster;
    return traced;
}

// The rows of budgets whose choice is the tracer rung: its image and tracing time.
void traced_budget_rows(const Run& c, const AccuracySweep& s, const Scene& scene, const std::vector<std::pair<std::string, double>>& traced,
                        std::vector<Row>& rows) {
    const Camera camera = scene.select_camera("", static_cast<float>(c.width) / static_cast<float>(c.height));
    for (const auto& [name, e] : traced) {
        const budget::Traced t = budget::trace_within(scene, c.shaders, camera, c.width, c.height, e);
        if (t.nonfinite_samples) throw Error(ExitCode::internal, s.effect + " " + name + ": non-finite samples in the traced frame");
        Row row;
        row.effect = s.effect;
        row.variant = name;
        char noise[32];
        std::snprintf(noise, sizeof noise, "%.4f", t.noise);
        row.settings = "--raytrace path, " + std::to_string(t.spp) + " spp (noise estimate " + noise + ")";
        row.scene = s.scene;
        row.width = c.width;
        row.height = c.height;
        row.ms = row.frame_ms = t.ms;
        row.image = t.image;
        rows.push_back(std::move(row));
        c.progress.step(s.effect + ": " + name);
    }
}

}  // namespace

void Progress::step(const std::string& what) {
    ++done;
    observer.step(done, total, what, std::chrono::duration<double>(Clock::now() - start).count());
}

Section run_job(const Run& c, const AccuracySweep& s, const std::string& job_scene, std::vector<Row>& rows) {
    const Options& o = c.o;
    Progress& progress = c.progress;
    const auto start = Clock::now();
    Section sec;
    sec.sweep = &s;
    sec.scene = section_scene(s, job_scene);
    sec.first = rows.size();
    if (s.effect == "forward_deferred") {
        for (int n : light_counts(o.quick)) {
            const std::string name = "generated:lights:" + std::to_string(n);
            const Scene scene = load_scene(o, name);
            GpuScene gpu(scene);
            AccuracySweep t = s;
            t.scene = name;
            // No effects: the shading itself (an effect's passes would cost the same on both paths).
            t.variants = {{"forward " + std::to_string(n) + " lights", "none", {"render.path=forward"}},
                          {"deferred " + std::to_string(n) + " lights", "none", {"render.path=deferred"}}};
            raster_rows(c, t, scene, gpu, rows);
        }
    } else if (s.effect == "ray_tracer") {
        const Scene scene = load_scene(o, job_scene);
        GpuScene gpu(scene);
        const AccuracySweep::Reference path{rt::Mode::path, o.quick ? 32 : 256};
        const Reference ref = make_reference(c, scene, gpu, path, RenderSettings{});
        progress.step("ray_tracer: reference");
        sec.noise = ref.noise;
        sec.ref_spp = ref.spp;
        sec.reference = ref.image;
        for (int spp : spp_steps(o.quick)) {
            const rt::Result r = trace(c, scene, gpu, path, spp, 7, RenderSettings{});
            Row row;
            row.effect = s.effect;
            row.variant = std::to_string(spp) + " spp";
            row.settings = "--raytrace path --spp " + std::to_string(spp);
            row.scene = job_scene;
            row.width = c.width;
            row.height = c.height;
            row.ms = r.trace_ms;
            row.iqr = 0.0;
            row.frame_ms = r.trace_ms;
            row.image = r.image;
            measure_errors(row, r.image, ref, Buffer::radiance);
            rows.push_back(std::move(row));
            progress.step("ray_tracer: " + std::to_string(spp) + " spp");
        }
    } else if (s.effect == "ray_tracer_depth") {
        const Scene scene = load_scene(o, job_scene);
        GpuScene gpu(scene);
        const int spp = o.quick ? 16 : 64;
        auto row_for = [&](int depth) {
            AccuracySweep::Reference r{rt::Mode::path, spp};
            r.max_depth = depth;
            const rt::Result res = trace(c, scene, gpu, r, spp, 7, RenderSettings{});
            Row row;
            row.effect = s.effect;
            row.variant = depth < 0 ? std::string("no cap (default)") : "max depth " + std::to_string(depth);
            row.settings = "--raytrace path --spp " + std::to_string(spp) + (depth < 0 ? "" : " --max-depth " + std::to_string(depth));
            row.scene = job_scene;
            row.width = c.width;
            row.height = c.height;
            row.ms = row.frame_ms = res.trace_ms;
            row.iqr = 0.0;
            row.image = res.image;
            return row;
        };
        Row unbounded = row_for(-1);
        progress.step("ray_tracer_depth: no cap");
        // The same paths up to the cap: no noise between the rows, only the dropped light.
        const Reference ref{unbounded.image, {}, 0.0, unbounded.ms, spp};
        sec.noise = 0.0;
        sec.ref_spp = spp;
        sec.reference = ref.image;
        for (int depth : depth_steps(o.quick)) {
            Row row = row_for(depth);
            measure_errors(row, row.image, ref, Buffer::radiance);
            rows.push_back(std::move(row));
            progress.step("ray_tracer_depth: max depth " + std::to_string(depth));
        }
        measure_errors(unbounded, unbounded.image, ref, Buffer::radiance);
        rows.push_back(std::move(unbounded));
    } else {
        Scene scene = load_scene(o, job_scene);
        const RenderSettings base = variant_settings(s, s.variants.front());
        const SceneTime when = pose_for_sweep(scene, base);  // animated: animation 0 at its midpoint
        GpuScene gpu(scene);
        set_sweep_motion(gpu, when);
        const Reference ref = make_reference(c, scene, gpu, *s.reference, base, &when);
        progress.step(s.effect + ": reference");
        std::optional<Reference> split;
        if (s.split) {
            split = make_reference(c, scene, gpu, *s.split, base, &when);
            sec.occlusion_rmse = compare(ref.image, split->image, 2.0 / 255.0).rmse;
            progress.step(s.effect + ": reference without occlusion");
        }
        AccuracySweep t = s;
        t.scene = job_scene;
        const auto traced = resolve_budget_variants(c, t, scene);
        raster_rows(c, t, scene, gpu, rows);
        traced_budget_rows(c, t, scene, traced, rows);
        for (size_t i = sec.first; i < rows.size(); ++i) {
            if (s.region == AccuracySweep::Region::edges) measure_edge_errors(rows[i], rows[i].image, ref);
            else measure_errors(rows[i], rows[i].image, ref, s.buffer);
            if (split) rows[i].rmse_no_occlusion = compare(rows[i].image, split->image, 2.0 / 255.0).rmse;
        }
        // On the edge pixels the noise is the reference's there (measure_edge_errors).
        sec.noise = s.region == AccuracySweep::Region::edges && rows.size() > sec.first ? rows[sec.first].ref_noise : ref.noise;
        sec.rt_ms = ref.ms;
        sec.ref_spp = ref.spp;
        sec.reference = ref.image;
    }
    sec.last = rows.size();
    mark_pareto(rows, sec.first);
    for (size_t i = sec.first; i < sec.last; ++i)
        if (!std::isfinite(rows[i].rmse)) rows[i].pareto = false;
    const int k = knee(rows, sec.first, sec.last);
    if (k >= 0) sec.knee_name = rows[static_cast<size_t>(k)].variant;
    sec.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    return sec;
}

std::optional<Gl> open_gl(const Options& o, Observer& observer) {
    ContextOptions co;
    Gl gl{create_context(o.backend, co), {}};
    if (!gl.ctx.context) {
        observer.message(gl.ctx.error);
        return std::nullopt;
    }
    if (!gl.ctx.notice.empty()) observer.message("warning: " + gl.ctx.notice);
    gl.device = {gl.ctx.context->device_string(), to_string(gl.ctx.context->backend())};
    return gl;
}

}  // namespace candela::accuracy
