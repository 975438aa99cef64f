#include "effects/ssao/ssao_sweep.hpp"

#include <string>

#include "render/features.hpp"

namespace candela {

std::vector<AccuracySweep> ssao_accuracy_sweeps(bool quick) {
    AccuracySweep s;
    s.effect = "ssao";
    s.scene = "shadow_test.gltf";
    s.buffer = AccuracySweep::Buffer::ao;
    s.own_passes = {"depth_normal_prepass", "ssao", "ssao_blur_x", "ssao_blur_y"};
    s.reference = AccuracySweep::Reference{rt::Mode::ao, quick ? 16 : 64};
    s.compared = "AO buffer (`--output-buffer ao`) vs `--raytrace ao` at the same radius";
    s.reading = "Screen space sees only the depth buffer: occluders behind the first surface or outside the "
                "view are missing (a bias more samples cannot fix), and few samples add noise that the "
                "depth-aware blur trades for smoothing across edges.";
    const std::vector<int> samples = quick ? std::vector<int>{4, 16} : std::vector<int>{4, 8, 16, 32};
    for (const char* res : {"half", "full"})
        for (int blur : quick ? std::vector<int>{4} : std::vector<int>{0, 4})
            for (int n : samples)
                s.variants.push_back({std::to_string(n) + " samples " + res + " blur " + std::to_string(blur), "ssao",
                                      {"ssao.samples=" + std::to_string(n), std::string("ssao.resolution=") + res,
                                       "ssao.blur=" + std::to_string(blur)}});
    s.shipped = "16 samples half blur 4";
    s.needed = [](const Features& f) { return f.environment; };
    return {s};
}

}  // namespace candela
