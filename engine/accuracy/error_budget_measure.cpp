#include "accuracy/error_budget_measure.hpp"

#include <algorithm>
#include <functional>
#include <memory>

#include "core/error.hpp"
#include "effects/gi/estimate.hpp"
#include "render/features.hpp"
#include "render/gpu_scene.hpp"
#include "rt/ray_tracer.hpp"
#include "rt/tracer_options.hpp"

namespace candela::budget {

SceneStats scene_stats(const Scene& scene, const ShaderLibrary& shaders, const Camera& camera, float aspect) {
    SceneStats s;
    const Features f = analyze(scene, RenderSettings{});
    s.punctual = f.punctual_lights;
    s.shadowed = f.scene.shadows.needed;
    s.emissive = f.scene.emissive_primitives;
    s.environment = f.scene.environment.needed;
    s.metal = f.scene.reflections.needed;
    s.transmission = f.scene.transmission.needed;
    s.blend = f.scene.transparency.needed;
    if (scene.triangle_count() > 0) {
        GpuScene gpu(scene);
        const IndirectEstimate e = estimate_indirect(shaders, scene, gpu, camera, aspect);
        s.indirect = e.fraction;
        const int pixels = e.width * e.height;
        s.coverage = pixels > 0 ? static_cast<double>(e.surface_pixels) / pixels : 0.0;
    }
    return s;
}

double block_error(const ImageF& a, const ImageF& b) { return block_agreement(a, b, 4).mean_abs; }

Reference path_reference(const Scene& scene, const ShaderLibrary& shaders, const Camera& camera, int width, int height, int spp,
                         std::uint32_t seed) {
    Reference r;
    const int half = std::max(1, spp / 2);
    GpuScene gpu(scene);
    rt::Options o = rt::tracer_options(RenderSettings{});
    o.mode = rt::Mode::path;
    o.spp = half;
    ImageF halves[2];
    for (int i = 0; i < 2; ++i) {
        o.seed = seed + static_cast<std::uint32_t>(i);
        rt::RayTracer tracer(shaders, scene, gpu, o);
        rt::Result t = tracer.render(camera, width, height);
        r.ms += t.trace_ms;
        r.nonfinite_samples += t.nonfinite_samples;
        halves[i] = std::move(t.image);
    }
    r.spp = 2 * half;
    r.noise = 0.5 * block_error(halves[0], halves[1]);
    r.image = halves[0];
    for (size_t i = 0; i < r.image.pixels.size(); ++i) r.image.pixels[i] = 0.5f * (halves[0].pixels[i] + halves[1].pixels[i]);
    return r;
}

TraceRung::TraceRung(const Scene& scene, const ShaderLibrary& shaders, const Camera& camera, int width, int height)
    : camera_(camera), width_(width), height_(height), gpu_(std::make_unique<GpuScene>(scene)) {
    rt::Options o = rt::tracer_options(RenderSettings{});
    o.mode = rt::Mode::path;
    o.seed = kTraceSeed;
    tracer_ = std::make_unique<rt::RayTracer>(shaders, scene, *gpu_, o);
}

TraceRung::~TraceRung() = default;

void TraceRung::step() {
    const int per_half = rounds_ == 0 ? kTraceMinSpp / 2 : spp_ / 2;
    for (int h = 0; h < 2; ++h) {
        tracer_->set_seed(kTraceSeed + static_cast<std::uint32_t>(2 * rounds_ + h));
        tracer_->set_spp(per_half);
        rt::Result r = tracer_->render(camera_, width_, height_);
        ms_ += r.trace_ms;
        nonfinite_ += r.nonfinite_samples;
        if (rounds_ == 0) {
            halves_[h] = std::move(r.image);
        } else {  // the new round has as many samples as the half so far: the mean of the two
            for (size_t i = 0; i < halves_[h].pixels.size(); ++i)
                halves_[h].pixels[i] = 0.5f * (halves_[h].pixels[i] + r.image.pixels[i]);
        }
    }
    spp_ += 2 * per_half;
    ++rounds_;
    noise_ = 0.5 * block_error(halves_[0], halves_[1]);
}

bool TraceRung::done(double target_noise) const { return spp_ >= kTraceMaxSpp || within(target_noise); }

ImageF TraceRung::image() const {
    ImageF m = halves_[0];
    for (size_t i = 0; i < m.pixels.size(); ++i) m.pixels[i] = 0.5f * (halves_[0].pixels[i] + halves_[1].pixels[i]);
    return m;
}

Traced trace_within(const Scene& scene, const ShaderLibrary& shaders, const Camera& camera, int width, int height, double budget) {
    TraceRung rung(scene, shaders, camera, width, height);
    const double target = kTraceNoiseShare * budget;
    do rung.step();
    while (!rung.done(target));
    Traced t;
    t.image = rung.image();
    t.noise = rung.noise();
    t.ms = rung.ms();
    t.spp = rung.spp();
    t.within = rung.within(target);
    t.nonfinite_samples = rung.nonfinite_samples();
    return t;
}

RenderSettings speed_of_light_settings() {
    RenderSettings s;
    apply_effects(s, "none");
    apply_knob(s, "render.path=forward");
    apply_knob(s, "forward.depth_prepass=1");
    return s;
}

SceneMeasurement measure_scene(const Scene& scene, const ShaderLibrary& shaders, const StillOptions& base, int reference_spp,
                               int frames, const std::vector<double>& trace_budgets) {
    SceneMeasurement m;
    const float aspect = static_cast<float>(base.width) / static_cast<float>(base.height);
    const Camera camera = with_lens(scene.select_camera(base.camera, aspect), base.settings);
    m.stats = scene_stats(scene, shaders, camera, aspect);
    // The frames first: their timing should not follow a long trace on a busy machine.
    std::vector<std::unique_ptr<FrameLoop>> loops;
    for (const Candidate& c : ladder()) {
        StillOptions o = base;
        o.settings = candidate_settings(c);
        o.output = FrameOutput::display;  // what a viewer's frame includes, as bench frame times it
        loops.push_back(std::make_unique<FrameLoop>(scene, shaders, o));
    }
    {
        StillOptions o = base;
        o.settings = speed_of_light_settings();
        o.output = FrameOutput::display;
        loops.push_back(std::make_unique<FrameLoop>(scene, shaders, o));
    }
    for (auto& loop : loops) loop->warmup(2);  // the first frames also JIT-compile llvmpipe's shaders
    for (int f = 0; f < frames; ++f)
        for (auto& loop : loops) loop->measure_frame();
    std::vector<StillResult> results;
    for (auto& loop : loops) results.push_back(loop->finish());
    loops.clear();
    m.light_ms = results.back().median_frame_ms();
    m.reference = path_reference(scene, shaders, camera, base.width, base.height, reference_spp);
    for (size_t i = 0; i < ladder().size(); ++i) {
        CandidateResult c;
        c.candidate = static_cast<int>(i);
        c.nonfinite = count_nonfinite(results[i].radiance);
        c.error = block_error(results[i].radiance, m.reference.image);
        c.ms = results[i].median_frame_ms();
        c.ratio = m.light_ms > 0 ? c.ms / m.light_ms : 0.0;
        m.candidates.push_back(c);
    }
    // The tracer rung: one run, read where each budget's target is first reached (largest first).
    std::vector<double> budgets = trace_budgets;
    std::sort(budgets.begin(), budgets.end(), std::greater<>());
    if (!budgets.empty()) {
        TraceRung rung(scene, shaders, camera, base.width, base.height);
        for (const double e : budgets) {
            const double target = kTraceNoiseShare * e;
            while (rung.spp() == 0 || !rung.done(target)) rung.step();
            SceneMeasurement::TraceResult t;
            t.budget = e;
            const ImageF image = rung.image();
            t.error = block_error(image, m.reference.image);
            t.noise = rung.noise();
            t.ms = rung.ms();
            t.spp = rung.spp();
            t.within = rung.within(target);
            t.nonfinite = rung.nonfinite_samples();
            m.traces.push_back(t);
        }
    }
    return m;
}

}  // namespace candela::budget
