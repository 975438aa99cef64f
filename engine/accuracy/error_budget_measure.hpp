#pragma once
// The GL side of error-budgeted rendering (error_budget.hpp): the scene statistics a prediction
// reads, the path reference with a bound on its own noise, and the measurements the model is
// fitted on (`candela bench error-budget`). Needs a current GL context.
#include <cstdint>
#include <string>
#include <vector>

#include "accuracy/error_budget.hpp"
#include "image/image.hpp"
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
};
// Renders every candidate of the ladder and the speed-of-light frame (interleaved, frame by
// frame, after two warm-up frames each) and the path reference at base.width x base.height.
// base: the scene's still options (camera, size, shared programs); its settings are replaced.
SceneMeasurement measure_scene(const Scene& scene, const ShaderLibrary& shaders, const StillOptions& base, int reference_spp,
                               int frames);

// The speed-of-light settings of `candela bench frame`: a depth prepass and one forward pass.
RenderSettings speed_of_light_settings();

}  // namespace candela::budget
