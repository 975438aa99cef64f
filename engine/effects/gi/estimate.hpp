#pragma once
// The planner's estimate of how much of the image is diffuse indirect light (issue 24): tiny
// `direct` and `indirect` (one diffuse bounce) renders from the scene's default camera, with
// Candela's own tracer, the bounces after the first extrapolated as a geometric series. Pixels
// of the camera's view that are emitters (above 10x the median direct light) are left out. The GI effect plans its probes from it (engine/effects/gi/gi.cpp).
#include <string>

namespace candela {

class GpuScene;
class ShaderLibrary;
struct Scene;

struct IndirectEstimate {
    double fraction = 0.0;         // rho = I1 / D (at most 0.99; 0 for a black image): the share of every bounce
    double direct_mean = 0.0;      // D: mean luminance of `direct` (emission, sky, direct light)
    double one_bounce_mean = 0.0;  // I1: mean luminance of `indirect` (one diffuse bounce)
    int width = 0, height = 0, spp = 0;
    double ms = 0.0;         // wall time of the estimate (BVH, program, both renders)
    std::string text() const;  // "40 % of the image (one diffuse bounce / direct ..., 48x32 px x 8 spp, 90 ms)"
};

// Throws candela::Error if the tracer cannot be built (internal) or the scene is empty of
// triangles (nothing to estimate: callers treat that as fraction 0).
IndirectEstimate estimate_indirect(const ShaderLibrary& shaders, const Scene& scene, GpuScene& gpu);

}  // namespace candela
