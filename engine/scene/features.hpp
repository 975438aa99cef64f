#pragma once
// What a scene calls for (docs/design.md, "The frame graph"). The planner (render/features.hpp)
// keeps it in Features::scene and the effects decide from it; `candela info` prints it.
#include <string>
#include <vector>

#include "scene/scene.hpp"

namespace candela {

struct Feature {
    std::string name;
    bool needed = false;
    std::string reason;  // why it is on or off, for humans
};

struct SceneFeatures {
    Feature shadows, transparency, reflections, transmission, emissive_area_lights, environment, material_layers;
    int emissive_primitives = 0;  // drawn primitives with an emissive material (raster area lights)
    std::vector<const Feature*> all() const {
        return {&shadows, &transparency, &reflections, &transmission, &emissive_area_lights, &environment, &material_layers};
    }
};

// `reflection_roughness`: metallic materials rougher than this do not call for reflections.
SceneFeatures analyze_features(const Scene& scene, float reflection_roughness = 0.3f);

}  // namespace candela
