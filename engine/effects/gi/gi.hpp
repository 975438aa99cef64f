#pragma once
// Diffuse global illumination from irradiance probes updated by Candela's own compute tracer
// (engine/effects/gi/; Majercik et al. 2019, "Dynamic Diffuse Global Illumination with Ray-Traced
// Irradiance Fields"): a grid of probes over the scene traces rays with the tracer's BVH; each hit
// reflects its direct light plus the previous iteration's probes, so every iteration adds a
// bounce. The planner runs it only where the scene's indirect light is a sizeable part of the
// image (estimate.hpp), with as many bounces as that fraction calls for.
#include <glm/glm.hpp>

#include "render/effect.hpp"

namespace candela {

struct IndirectEstimate;

struct GiOptions {
    int probes = 8;           // [2, 32] probes along the scene's longest axis (the others in proportion)
    bool dense = true;        // more probes where they carry more of the light (gi_planned_probes)
    int rays = 64;            // [64, 2048] rays per probe and update, rounded up to a multiple of 64
    int bounces = 0;          // [0, 64] iterations that each add a bounce; 0: planned from the estimate
    int iterations = 6;       // [1, 512] updates after the bounces, which average (a still does all before its frame)
    // [0, 1] indirect fraction of the image from which the probes run (0: always). Leaving the
    // indirect light out costs the image that fraction of its light: at 5 % the default image
    // keeps 3 of the 8 % of the tracer's mean that the random-scene tests hold it to for the
    // other approximations.
    float threshold = 0.05f;
    // [0, 1] the probes run too when at least this share of the surface in view is lit visibly
    // by indirect light alone (IndirectEstimate::indirect_only_share), whatever the image-wide
    // fraction: such a region goes black without them. 1: never. 1 % is the share of 4x4 blocks
    // beyond the random-scene tests' 99th-percentile rule.
    float indirect_only = 0.01f;
    int budget = 0;           // [0, 2^26] rays per frame (the viewer); 0: converge before the frame
    bool restart = false;     // start over every frame (a scene that changes every frame; bench accuracy)
    float inset = 0.15f;      // [0.01, 0.5] outer probes' distance from the scene's bounds, in cells
    float bias = 0.3f;        // [0, 1] shading offset off the surface, in units of 0.75 x the smallest spacing
};

// The bounces the planner gives the probes: gi.bounces if set, else from the estimate's measured
// first and second bounce (later ones extrapolated with the ratio of the second to the first):
// enough bounces to leave less than 0.5 % of the image's light out, less the iterations/2 more
// that the averaging updates after them add on average.
int gi_planned_bounces(const GiOptions& o, const IndirectEstimate* estimate);
// Probes along the scene's longest axis: gi.probes, or with gi.dense and an estimate, more where
// the probes carry more of the image's light. Trilinear interpolation of a smooth irradiance
// field errs in proportion to the square of the spacing, and the image takes that error in
// proportion to its indirect share s; holding s x spacing^2 at what gi.probes gives at s = 25 %
// keeps the probes' part of the image's error there: gi.probes x sqrt(s / 0.25), from gi.probes
// up to twice it (8x the probes, the cost's bound).
int gi_planned_probes(const GiOptions& o, const IndirectEstimate* estimate);
// The estimate the planner had (Features::estimates, Effect::view_estimate), or nullptr.
const IndirectEstimate* indirect_estimate(const Features& f);

// What the GI runtime has done (tests; the viewer reads it as EffectRuntime::progress()):
// renderer.effect_runtime<GiStatusView>().
struct GiStatus {
    bool planned = false;
    glm::ivec3 counts{0};       // probes per axis
    int rays = 0;               // per probe and update
    int bounces = 0;            // updates that each add a bounce
    int updates_done = 0;       // complete updates of every probe so far
    int updates_planned = 0;    // bounces + gi.iterations
    long long rays_last_frame = 0;
    unsigned nonfinite = 0;     // NaN/Inf ray results replaced by 0 (should stay 0)
    bool converged() const { return updates_done >= updates_planned; }
};
class GiStatusView {
public:
    virtual ~GiStatusView() = default;
    virtual GiStatus gi_status() const = 0;
};

// GI probes in an interactive front end (Effect::interactive_defaults): a still converges them
// before its frame (gi.budget 0); the viewer spreads their updates over frames so that the first
// frame and every frame after a change stay interactive. 16384 rays per frame is 256 probes of 64
// rays (the default; 128 of 128): whole 64-probe batches of the GI pass, so the updates happen in
// the same batches as in a still and the converged image equals `candela render`'s. Measured on
// llvmpipe, 2 shared cores, cornell_point (docs/cli.md, the viewer).
constexpr int kGiInteractiveBudget = 16384;

// The progress line (EffectProgress::line): how far the probes are and at what budget (rays per
// frame, 0: all before the frame). Empty when the probes are not planned.
std::string gi_status_line(const GiStatus& st, int budget);

const Effect& gi_effect();

}  // namespace candela
