#pragma once
// analyze(scene, settings): which effects this scene calls for, and which passes therefore run
// (shared/DESIGN.md section 2). An effect that is switched on but not needed is not planned, and
// the reason says why, for `candela info` and the stats.
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "render/settings.hpp"
#include "scene/features.hpp"
#include "scene/scene.hpp"

namespace candela {

struct EffectDecision {
    std::string name;
    bool enabled = false;      // the switch in RenderSettings
    bool needed = false;       // the scene calls for it
    bool implemented = false;  // a pass exists for it in this build
    bool planned = false;      // enabled && needed && implemented
    std::string reason;        // "on: 5 BLEND materials", "off: no BLEND materials", ...
};

struct Features {
    EffectDecision shadows, ssao, rsm, transparency, reflections;
    bool environment = false;  // sky pass and ambient term
    int punctual_lights = 0;
    int area_light_pieces = 0;  // emissive primitives drawn * arealight.samples
    bool deferred = false;      // the render path
    std::string path_reason;
    SceneFeatures scene;
    std::vector<const EffectDecision*> effects() const { return {&shadows, &ssao, &rsm, &transparency, &reflections}; }
};

Features analyze(const Scene& scene, const RenderSettings& settings);

// The raster passes a frame runs, in order, with the reason for each; the renderer builds its
// frame graph from exactly this list (so `candela info` shows what will run).
struct PlannedPass {
    std::string name;
    std::string why;
};
std::vector<PlannedPass> plan_passes(const Features& features, const RenderSettings& settings);
nlohmann::json to_json(const Features& features);

}  // namespace candela
