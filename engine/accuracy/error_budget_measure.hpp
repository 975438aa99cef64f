#pragma once
// The GL side of error-budgeted rendering (error_budget.hpp): the scene statistics a prediction
// reads, the path reference with a bound on its own noise, and the measurements the model is
// fitted on (`candela bench error-budget`). Needs a current GL context.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "accuracy/error_budget.hpp"
#include "image/image.hpp"
#include "render/gpu_scene.hpp"
#include "rt/ray_tracer.hpp"
#include "render/still.hpp"
#include "scene/scene.hpp"
#include "shader/shader_library.hpp"

namespace candela::budget {

// Statistics of `scene` seen from `camera`: the GI planner's indirect estimate (a tiny trace
// from the camera, effects/gi/estimate.hpp) and the scene features (lights, materials).
SceneStats scene_stats(const Scene& scene, const ShaderLibrary& shaders, const Camera& camera, float aspect);

// The block metric: block_agreement(a, b, 4).mean_abs (display values, 4x4 blocks).
double block_error(const ImageF& a, const ImageF& b);

// `--raytrace path` at `spp` as the mean of two independent halves (seeds `seed` and `seed` + 1).
// noise = half the block error between the halves: about the block error of the mean against the
// converged image (each half's noise is sqrt(2) times the mean's, and their difference's
// sqrt(2) times a half's). A measured error e then lies within about e +- noise of the error
// against the converged reference.
struct Reference {
    ImageF image;
    double noise = 0;
    double ms = 0;
    int spp = 0;
    unsigned nonfinite_samples = 0;
};
Reference path_reference(const Scene& scene, const ShaderLibrary& shaders, const Camera& camera, int width, int height, int spp,
                         std::uint32_t seed = 1);

// The tracer rung (Choice::trace): `--raytrace path` in rounds, as two independent halves whose
// block difference estimates the mean's own noise (as Reference::noise). The first round traces
// kTraceMinSpp / 2 samples per half, each later round as many as the half has, so the samples
// double; round k of half h uses seed kTraceSeed + 2k + h, seeds no --seed can give (a reference
// with the default seeds 1 and 2 is independent of it). Deterministic: a run that stops at a
// larger target is the prefix of one that goes on to a smaller target.
constexpr std::uint32_t kTraceSeed = 0xC0000000u;
class TraceRung {
public:
    TraceRung(const Scene& scene, const ShaderLibrary& shaders, const Camera& camera, int width, int height);
    ~TraceRung();
    void step();                     // one more round (doubles the samples)
    // Within the target (and at least kTraceMinSpp samples), or at kTraceMaxSpp.
    bool done(double target_noise) const;
    bool within(double target_noise) const { return spp_ >= kTraceMinSpp && noise_ <= target_noise; }
    int spp() const { return spp_; }          // both halves together
    double noise() const { return noise_; }   // 0.5 * block error between the halves
    double ms() const { return ms_; }         // tracing time so far
    unsigned nonfinite_samples() const { return nonfinite_; }
    ImageF image() const;                     // the mean of the halves
private:
    const Camera camera_;
    int width_, height_;
    std::unique_ptr<GpuScene> gpu_;
    std::unique_ptr<rt::RayTracer> tracer_;
    ImageF halves_[2];
    int rounds_ = 0, spp_ = 0;
    double noise_ = 0, ms_ = 0;
    unsigned nonfinite_ = 0;
};
// Traces until the noise estimate is within kTraceNoiseShare * budget or kTraceMaxSpp.
struct Traced {
    ImageF image;
    double noise = 0, ms = 0;
    int spp = 0;
    bool within = false;  // the noise estimate reached the target
    unsigned nonfinite_samples = 0;
};
Traced trace_within(const Scene& scene, const ShaderLibrary& shaders, const Camera& camera, int width, int height, double budget);

// One candidate measured on one scene.
struct CandidateResult {
    int candidate = -1;   // in ladder()
    double error = 0;     // block error against the reference
    double ms = 0;        // median frame time (render + glFinish)
    double ratio = 0;     // ms / the speed-of-light frame's median
    std::size_t nonfinite = 0;
};
struct SceneMeasurement {
    SceneStats stats;
    Reference reference;
    double light_ms = 0;  // the speed-of-light frame (depth prepass + forward, no effect)
    std::vector<CandidateResult> candidates;
    // The tracer rung at each of the measured budgets: what render --error-budget E traces.
    struct TraceResult {
        double budget = 0, error = 0, noise = 0, ms = 0;
        int spp = 0;
        bool within = false;
        unsigned nonfinite = 0;
    };
    std::vector<TraceResult> traces;
};
// Renders every candidate of the ladder and the speed-of-light frame (interleaved, frame by
// frame, after two warm-up frames each) and the path reference at base.width x base.height.
// base: the scene's still options (camera, size, shared programs); its settings are replaced.
// trace_budgets: the budgets at which the tracer rung is measured (one progressive run, read at
// the round where each budget's target is first reached).
SceneMeasurement measure_scene(const Scene& scene, const ShaderLibrary& shaders, const StillOptions& base, int reference_spp,
                               int frames, const std::vector<double>& trace_budgets = {});

// The speed-of-light settings of `candela bench frame`: a depth prepass and one forward pass.
RenderSettings speed_of_light_settings();

}  // namespace candela::budget
