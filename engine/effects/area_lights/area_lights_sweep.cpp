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
    s.compared = "final colour vs `--raytrace direct`; the rasterizer splits each emissive primitive into `arealight.samples` shadowed pieces";
    s.reading = "Few pieces give banded, too-hard shadows and a wrong near-field falloff; each piece costs a "
                "shadow map and a light in the shading loop, so time grows linearly with the sample count - up to "
                "`shadows.max_lights` (16) shadowed lights: pieces beyond it get no shadow map, so 32 pieces cost "
                "little more than 16 and light through their occluders.";
    for (int n : quick ? std::vector<int>{1, 4, 16} : std::vector<int>{1, 4, 16, 32})
        s.variants.push_back({std::to_string(n) + " pieces", "shadows", {"arealight.samples=" + std::to_string(n)}});
    s.shipped = "4 pieces";
    s.needed = [](const Features& f) { return f.scene.emissive_area_lights.needed; };
    return {s};
}

}  // namespace candela
