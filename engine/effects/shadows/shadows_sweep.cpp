#include "effects/shadows/shadows_sweep.hpp"

#include <string>

#include "render/features.hpp"

namespace candela {

std::vector<AccuracySweep> shadows_accuracy_sweeps(bool quick) {
    std::vector<AccuracySweep> sweeps;
    {
        AccuracySweep s;
        s.effect = "shadows";
        s.scene = "shadow_test.gltf";
        s.buffer = AccuracySweep::Buffer::visibility;
        s.own_passes = {"shadow_maps", "forward_opaque"};
        s.reference = AccuracySweep::Reference{rt::Mode::visibility, quick ? 4 : 16};
        s.compared = "visibility of light 0 (the spot light): `--output-buffer visibility` vs `--raytrace visibility`";
        s.reading = "The error is made of aliasing at shadow edges (resolution), the filter's penumbra against the "
                    "light's true one (a light's size gives a real penumbra that hard and fixed "
                    "PCF kernels miss), and light leaking or acne where the bias is wrong. The time is the shadow-map "
                    "pass plus the shading pass that filters.";
        const std::vector<int> resolutions = quick ? std::vector<int>{512, 1024} : std::vector<int>{512, 1024, 2048};
        for (int r : resolutions)
            for (const char* f : {"hard", "pcf", "pcss"})
                s.variants.push_back({std::string(f) + " " + std::to_string(r), "shadows",
                                      {"shadows.resolution=" + std::to_string(r), std::string("shadows.filter=") + f}});
        if (!quick)
            for (int k : {3, 9})
                s.variants.push_back({"pcf" + std::to_string(k) + " 1024", "shadows",
                                      {"shadows.resolution=1024", "shadows.filter=pcf", "shadows.pcf_size=" + std::to_string(k)}});
        for (const char* b : {"0", "4"})
            s.variants.push_back({std::string("pcss 1024 normal_bias ") + b, "shadows",
                                  {"shadows.resolution=1024", "shadows.filter=pcss", std::string("shadows.normal_bias=") + b}});
        s.shipped = "pcss 1024";
        s.needed = [](const Features& f) { return f.decision("shadows").needed && f.punctual_lights > 0; };
        sweeps.push_back(s);
    }
    {
        AccuracySweep s;
        s.effect = "shadows_colour";
        s.scene = "shadow_test.gltf";
        s.own_passes = {"shadow_maps", "forward_opaque"};
        s.reference = AccuracySweep::Reference{rt::Mode::direct, quick ? 16 : 64};
        s.compared = "final colour with shadows only vs `--raytrace direct` (exact visibility, one bounce)";
        s.reading = "On top of the visibility error, the colour error holds what the raster path leaves out of "
                    "direct light (the environment's occlusion, which SSAO would approximate and is off here) - "
                    "a floor no shadow setting removes.";
        for (const char* f : {"hard", "pcf", "pcss"})
            s.variants.push_back({std::string(f) + " 1024", "shadows", {std::string("shadows.filter=") + f}});
        s.shipped = "pcss 1024";
        s.needed = [](const Features& f) { return f.decision("shadows").needed; };
        sweeps.push_back(s);
    }
    return sweeps;
}

}  // namespace candela
