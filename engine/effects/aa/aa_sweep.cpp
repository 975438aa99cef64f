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
                "pixel break into dashes and the fence's alpha-tested bars alias. Each doubling of the samples roughly "
                "halves the edge error. Forward multisampling shades once per pixel and alpha to coverage anti-aliases "
                "the MASK fence; deferred shades per sample only at the edge pixels of the multisampled G-buffer "
                "(its MASK contours stay aliased: the G-buffer keeps the alpha test). On llvmpipe 2 and 8 samples are "
                "made of two sub-frames (the device multisamples 4 only), so they cost about twice 1 and 4. The fence is "
                "where the counts differ least: sub-frames alpha-test every sample exactly, while alpha to coverage "
                "estimates a fragment's coverage from the alpha at its centre (a ramp over fwidth), which under the "
                "texture's minification covers the bars too generously.";
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
