// Anti-aliasing's accuracy sweep (bench accuracy, section "aa"): the raster image of
// generated:edges on both paths at 1, 2, 4 and 8 samples against the tracer's box-filtered pixels
// with a single bounce and exact visibility (`--raytrace direct`, jittered camera rays), the
// error measured on the edge pixels only.
#include "effects/aa/aa_sweep.hpp"

#include <string>

#include "render/features.hpp"

namespace candela {

std::vector<AccuracySweep> aa_accuracy_sweeps(bool quick) {
    AccuracySweep s;
    s.effect = "aa";
    s.scene = "generated:edges";
    s.region = AccuracySweep::Region::edges;
    s.reference = AccuracySweep::Reference{rt::Mode::direct, quick ? 32 : 256};
    s.reference->jitter = 1;  // the box-filtered pixel: what anti-aliasing approximates
    s.compared = "radiance of generated:edges (`--effects none`: the edges alone) vs `--raytrace direct` with jittered camera "
                 "rays (the pixel's box-filtered average), on the edge pixels only; time = the whole frame";
    s.reading = "One sample per pixel is a point sample: a partly covered pixel is all or nothing, wires thinner than a "
                "pixel break into dashes and the fence's alpha-tested bars alias. Two samples halve the edge error; "
                "beyond that the fence limits the gain: sub-frames alpha-test every sample exactly, while alpha to "
                "coverage (4x, and each 4x sub-frame of 8) estimates a fragment's coverage from the alpha at its centre "
                "(a ramp over fwidth), which under the texture's minification covers the bars too generously; without "
                "it the fence is not anti-aliased at all (the 'no alpha to coverage' row). Forward shades once per "
                "pixel; deferred shades once per surface a pixel's samples show, so its extra cost is at the edges. "
                "On llvmpipe 2 and 8 samples are two sub-frames (the device multisamples 4 only) and cost about twice "
                "1 and 4.";
    // --quick (CI): every count on forward, the device's own count on deferred.
    for (const char* path : {"forward", "deferred"}) {
        const std::string p = std::string("render.path=") + path;
        s.variants.push_back({std::string(path) + " 1 sample (aa off)", "none", {p, "aa.mode=off"}});
        for (int n : {2, 4, 8}) {
            if (quick && std::string(path) == "deferred" && n != 4) continue;
            s.variants.push_back({std::string(path) + " " + std::to_string(n) + " samples", "none",
                                  {p, "aa.mode=msaa", "aa.samples=" + std::to_string(n)}});
        }
    }
    if (!quick)
        s.variants.push_back({"forward 4 samples, no alpha to coverage", "none",
                              {"render.path=forward", "aa.mode=msaa", "aa.samples=4", "aa.alpha_to_coverage=0"}});
    s.shipped = "forward 1 sample (aa off)";
    s.needed = [](const Features&) { return true; };
    return {s};
}

}  // namespace candela
