#include "effects/rsm/rsm_sweep.hpp"

#include <string>

#include "render/features.hpp"

namespace candela {

std::vector<AccuracySweep> rsm_accuracy_sweeps(bool quick) {
    AccuracySweep s;
    s.effect = "rsm";
    s.scene = "cornell_point.gltf";
    s.buffer = AccuracySweep::Buffer::indirect;
    s.own_passes = {"depth_normal_prepass", "rsm", "rsm_indirect"};
    s.reference = AccuracySweep::Reference{rt::Mode::indirect, quick ? 32 : 128};
    s.split = AccuracySweep::Reference{rt::Mode::indirect, quick ? 32 : 128, -1, 0, false};
    s.compared = "one-bounce indirect light (`--output-buffer indirect`) vs `--raytrace indirect`; the column "
                 "`rmse_no_occlusion` compares with the tracer's indirect light without visibility between the "
                 "bounce points (RSM's own model), which isolates RSM's sampling error";
    s.reading = "RSM's error is its sampling (few texels of the light's view per pixel: noise and blotches) plus "
                "the occlusion it ignores between the bounce point and the receiver (light leaks behind "
                "objects). Only the first shrinks with samples and resolution. A full-resolution gather has no "
                "bilateral upsampling to average its noise, so at equal samples it is noisier than the "
                "half-resolution one, and costs up to four times as much.";
    for (int res : quick ? std::vector<int>{128, 256} : std::vector<int>{128, 256, 512})
        for (int n : quick ? std::vector<int>{16, 64} : std::vector<int>{16, 64, 256})
            for (const char* g : quick ? std::vector<const char*>{"half"} : std::vector<const char*>{"half", "full"})
                s.variants.push_back({std::to_string(n) + " samples " + std::to_string(res) + " " + g, "shadows,rsm",
                                      {"rsm.resolution=" + std::to_string(res), "rsm.samples=" + std::to_string(n),
                                       std::string("rsm.gather=") + g}});
    s.shipped = "64 samples 256 half";
    s.needed = [](const Features& f) { return f.decision("shadows").needed && (f.punctual_lights > 0 || f.scene.emissive_primitives > 0); };
    return {s};
}

}  // namespace candela
