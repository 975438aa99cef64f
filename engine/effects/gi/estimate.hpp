#pragma once
// The planner's estimate of how much of the image is indirect light: the view measurement of
// rt/view_light.hpp (tiny renders of the direct light on the surfaces the camera sees and of its
// first three bounces, from the render's own camera at its aspect), the bounces after the second
// extrapolated as a geometric series with the ratio the third had to the second. The GI effect
// plans its probes from it (engine/effects/gi/gi.cpp).
#include <memory>
#include <string>

#include "scene/scene.hpp"

namespace candela {

class GpuScene;
namespace rt {
class RtScene;
}
class ShaderLibrary;

// Fewer directly lit pixels than this and the estimate is not trusted: the planner then runs the
// probes (a wrong "off" loses light; a wrong "on" only costs time).
constexpr int kMinLitPixels = 32;

struct IndirectEstimate {
    double fraction = 0.0;         // I / (D + I): the indirect share of the seen surfaces' light
    double fraction_se = 0.0;      // standard error of B1 / D, the first bounce's ratio (errs large)
    double per_bounce = 0.0;       // r = B3 / B2: what each bounce after the second returns of the one before
    double direct_mean = 0.0;      // D: direct light the seen surfaces reflect (no emitter or sky in view)
    double one_bounce_mean = 0.0;  // B1: its first bounce on the same surfaces
    double two_bounce_mean = 0.0;  // B2: its second bounce
    int width = 0, height = 0, spp = 0;
    int surface_pixels = 0, lit_pixels = 0;
    bool trusted = false;          // lit_pixels >= kMinLitPixels
    double indirect_only_share = 0.0;  // ViewLight::indirect_only_share: surface lit visibly by indirect light alone
    double ms = 0.0;               // wall time of the estimate (BVH, programs, renders)
    std::string text() const;  // "40 % of the light on the image's surfaces (...)"
};

// From the render's camera at its aspect. Throws candela::Error if the tracer cannot be built
// (internal) or the scene has no triangles (callers treat that as fraction 0).
// `shared`: as measure_view_light's (rt/view_light.hpp).
IndirectEstimate estimate_indirect(const ShaderLibrary& shaders, const Scene& scene, GpuScene& gpu, const Camera& camera,
                                   float aspect, std::shared_ptr<rt::RtScene>* shared = nullptr);

}  // namespace candela
