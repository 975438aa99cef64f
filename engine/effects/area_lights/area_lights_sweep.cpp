#include "effects/area_lights/area_lights_sweep.hpp"

#include <string>

#include "render/features.hpp"

namespace candela {

std::vector<AccuracySweep> area_lights_accuracy_sweeps(bool quick) {
    AccuracySweep s;
    s.effect = "area_lights";
    s.scene = "cornell_box.gltf";
    s.own_passes = {"shadow_maps", "forward_opaque"};
    s.reference = AccuracySweep::Reference{rt::Mode::direct, quick ? 16 : 64};
    s.compared = "final colour vs `--raytrace direct`: emissive triangles as LTC polygon lights with the shadow ratio of "
                 "`arealight.samples` shadowed pieces (ltc), or the pieces themselves as point lights (pieces)";
    s.reading = "The pieces are Lambertian point lights: banded, too-hard shadows, a wrong near-field falloff and "
                "highlights brighter than the light on smooth surfaces. LTC integrates each triangle exactly over "
                "the cosine and a fitted GGX lobe (with a residual on 3x3 cells where the fit misses the lobe's "
                "tails and grazing shape), so unshadowed light is right for any piece count; the pieces "
                "only decide the shadows. Each piece costs a shadow map, up to `shadows.max_lights` (16).";
    for (int n : quick ? std::vector<int>{1, 4, 16} : std::vector<int>{1, 4, 16, 32})
        s.variants.push_back({"pieces " + std::to_string(n), "shadows", {"arealight.method=pieces", "arealight.samples=" + std::to_string(n)}});
    for (int n : quick ? std::vector<int>{1, 4} : std::vector<int>{1, 4, 16})
        s.variants.push_back({"ltc, " + std::to_string(n) + " shadow pieces", "shadows", {"arealight.method=ltc", "arealight.samples=" + std::to_string(n)}});
    // The LTC's residual (arealight.residual) off: what its 3x3 cells cost and what they buy.
    s.variants.push_back({"ltc, 4 shadow pieces, no residual", "shadows", {"arealight.method=ltc", "arealight.samples=4", "arealight.residual=0"}});
    s.shipped = "ltc, 4 shadow pieces";
    s.needed = [](const Features& f) { return f.scene.emissive_area_lights.needed; };
    return {s};
}

}  // namespace candela
