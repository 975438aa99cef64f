#include "effects/gi/gi_sweep.hpp"

#include <string>

#include "render/features.hpp"

namespace candela {

std::vector<AccuracySweep> gi_accuracy_sweeps(bool quick) {
    std::vector<AccuracySweep> out;
    // The shading every variant shares: the default effects, GI switched as the variant says.
    const std::string base = "shadows,reflections,ssao,transparency";
    for (const char* scene : {"cornell_point.gltf", "cornell_box.gltf"}) {
        if (quick && std::string(scene) == "cornell_box.gltf") continue;
        AccuracySweep s;
        s.effect = "gi";
        s.scene = scene;
        s.buffer = AccuracySweep::Buffer::radiance;
        s.own_passes = {};  // the whole frame: the variants differ in which passes they run
        s.reference = AccuracySweep::Reference{rt::Mode::path, quick ? 32 : 128};
        s.compared = "the whole image (default shading, indirect light as the variant says) vs `--raytrace path` "
                     "(every bounce)";
        s.reading = "Without indirect light the image misses everything after the first bounce. One-bounce RSM "
                    "adds the first of those bounces, with its sampling noise and without occlusion between the "
                    "bounce points. The probes carry every bounce, limited by their spacing (light between "
                    "probes is interpolated, and the Chebyshev test only approximates what each probe sees), by "
                    "rays per probe (noise) and by the bounces they were given. Their time is a still's: every update, "
                    "before the frame (gi.restart=1 repeats it each measured frame); a viewer spreads it over frames.";
        s.variants.push_back({"no indirect", base, {}});
        s.variants.push_back({"rsm one bounce", base + ",shadows,rsm", {}});
        const std::vector<int> probes = quick ? std::vector<int>{4, 8} : std::vector<int>{4, 8, 12};
        const std::vector<int> rays = std::vector<int>{64, 128};
        for (int p : probes)
            for (int r : rays)
                s.variants.push_back({"probes " + std::to_string(p) + " rays " + std::to_string(r), base + ",gi",
                                      {"gi.threshold=0", "gi.restart=1", "gi.probes=" + std::to_string(p), "gi.rays=" + std::to_string(r)}});
        for (int b : quick ? std::vector<int>{1} : std::vector<int>{1, 4})
            s.variants.push_back({"probes 8 rays 64 bounces " + std::to_string(b), base + ",gi",
                                  {"gi.threshold=0", "gi.restart=1", "gi.bounces=" + std::to_string(b)}});
        s.shipped = "probes 8 rays 64";
        s.needed = [](const Features&) { return true; };
        out.push_back(std::move(s));
    }
    return out;
}

}  // namespace candela
