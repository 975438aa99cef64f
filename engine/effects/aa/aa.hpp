#pragma once
// Anti-aliasing (engine/effects/aa/): multisampling on both render paths.
//   forward:  the colour and depth targets are multisampled; each fragment is shaded once and
//             covers the samples it hits (MASK materials write alpha to coverage).
//   deferred: the G-buffer is multisampled; the lighting pass shades once per pixel where all its
//             samples see the same surface and once per sample at the edge pixels only.
// The resolve pass (Stage::post) averages the samples (a box filter over the pixel, in linear
// radiance: the estimator the tracer's jittered camera rays compute) and writes the single-sample
// HDR output and a resolved depth for the post filters.
// A sample count the device cannot multisample (llvmpipe has only 4) is made of sub-frames:
// `samples` = device samples x sub-frames, each sub-frame with the projection shifted by a
// fraction of a pixel so that the union of the sample positions is a rook pattern (one sample per
// row and column of the pixel's N x N grid), every sample inside its pixel; the resolve averages
// the sub-frames.
#include <vector>

#include <glm/vec2.hpp>

#include "render/effect.hpp"

namespace candela {

enum class AaMode { off, msaa };
inline constexpr ChoiceName<AaMode> kAaModes[] = {{"off", AaMode::off}, {"msaa", AaMode::msaa}};

enum class AaSamples : int { x1 = 1, x2 = 2, x4 = 4, x8 = 8 };
inline constexpr ChoiceName<AaSamples> kAaSampleCounts[] = {
    {"1", AaSamples::x1}, {"2", AaSamples::x2}, {"4", AaSamples::x4}, {"8", AaSamples::x8}};

struct AaOptions {
    AaMode mode = AaMode::off;  // off by default: see docs/effects/aa.md (the goldens and every
                                // effect's accuracy sweep compare pixel-centre samples)
    AaSamples samples = AaSamples::x4;  // samples per pixel
    bool alpha_to_coverage = true;  // forward: MASK materials' coverage from their alpha
    // The specular lobe widened by how much the normal turns over the pixel (docs/effects/aa.md):
    // the box-filtered pixel of a highlight smaller than a pixel, which a few samples miss or hit.
    bool specular_filter = true;
};

// How this frame's samples are taken.
struct AaPlan {
    bool on = false;        // the resolve runs (the drawing targets are the AA ones)
    int samples = 1;        // per pixel in all
    int device_samples = 1; // multisampled targets' sample count (1: single-sample targets)
    int subframes = 1;      // samples / device_samples
    // Projection offsets of the sub-frames in pixels (x right, y up), centred on 0.
    std::vector<glm::vec2> offsets{glm::vec2(0.0f)};
};

// The sample counts the current GL context can multisample RGBA32F, RG16F, RGBA16F, RGBA8 and
// DEPTH32F textures with (1 always; queried once, on the first call with a context).
const std::vector<int>& device_sample_counts();
// The device's standard positions of `n` samples, pixel units from the pixel centre, y up
// (glGetMultisamplefv; queried once per count with the current context; n = 1: the centre).
const std::vector<glm::vec2>& device_sample_positions(int n);
// The plan for these settings (the device's counts from device_sample_counts()).
AaPlan aa_plan(const Features& f, const RenderSettings& s);
// The same for given device counts (tests).
AaPlan aa_plan_for(int samples, const std::vector<int>& device_counts, const std::vector<glm::vec2>& device_positions);

const Effect& aa_effect();

}  // namespace candela
