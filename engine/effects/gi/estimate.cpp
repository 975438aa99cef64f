#include "effects/gi/estimate.hpp"

#include <algorithm>
#include <cstdio>

#include "rt/view_light.hpp"

namespace candela {

std::string IndirectEstimate::text() const {
    char buf[400];
    std::snprintf(buf, sizeof buf,
                  "%.0f %% of the light on the image's surfaces (first bounce / direct %.2f +- %.2f, each later bounce x %.2f; "
                  "%dx%d px x %d spp, %d surface px, %d with direct light%s, %.1f %% lit by indirect light alone; %.0f ms)",
                  fraction * 100.0, direct_mean > 0.0 ? one_bounce_mean / direct_mean : 0.0, fraction_se, per_bounce, width, height, spp,
                  surface_pixels, lit_pixels, trusted ? "" : ": too few to trust", indirect_only_share * 100.0, ms);
    return buf;
}

IndirectEstimate estimate_indirect(const ShaderLibrary& shaders, const Scene& scene, GpuScene& gpu, const Camera& camera,
                                   float aspect, std::shared_ptr<rt::RtScene>* shared) {
    // The measurements share one tracer geometry (the caller's, if it keeps one).
    std::shared_ptr<rt::RtScene> local;
    if (!shared) shared = &local;
    // About 1536 pixels x 8 samples: each mean's standard error is a few tenths of a percent of
    // the image; the cost is the BVH and the programs. Where the lit surfaces in view are too
    // small at that size to hold kMinLitPixels pixels (a few objects against the sky), the view is
    // measured again at 4x and then 16x the pixels, so that the decision rests on a measurement
    // instead of the untrusted default. A view with no lit pixel at all is not measured again:
    // its light is all indirect (a room lit by what the camera does not see), and the probes run.
    ViewLight v = measure_view_light(shaders, scene, gpu, camera, aspect, 8, kViewLightPixels, shared);
    double ms = v.ms;
    for (int pixels = 4 * kViewLightPixels, round = 0; round < 2 && v.lit_pixels > 0 && v.lit_pixels < kMinLitPixels;
         pixels *= 4, ++round) {
        v = measure_view_light(shaders, scene, gpu, camera, aspect, 8, pixels, shared);
        ms += v.ms;
    }
    v.ms = ms;
    IndirectEstimate e;
    e.fraction = std::clamp(v.indirect_share, 0.0, 0.99);
    e.fraction_se = v.ratio_stderr;
    e.per_bounce = v.per_bounce;
    e.direct_mean = v.direct_mean;
    e.one_bounce_mean = v.bounce_mean;
    e.two_bounce_mean = v.second_bounce_mean;
    e.width = v.width;
    e.height = v.height;
    e.spp = v.spp;
    e.surface_pixels = v.surface_pixels;
    e.lit_pixels = v.lit_pixels;
    e.trusted = v.lit_pixels >= kMinLitPixels;
    e.indirect_only_share = v.indirect_only_share;
    e.ms = v.ms;
    return e;
}

}  // namespace candela
