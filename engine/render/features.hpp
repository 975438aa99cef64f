#pragma once
// analyze(scene, settings): which effects this scene calls for, and which passes therefore run
// (docs/design.md, "The frame graph"). An effect that is switched on but not needed is not planned, and
// the reason says why, for `candela info` and the stats.
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "render/effect.hpp"
#include "render/settings.hpp"
#include "scene/features.hpp"
#include "scene/scene.hpp"

namespace candela {

// The most lights the forward pass's per-tile light masks hold (forward/light_tiles.comp).
inline constexpr int kMaxTiledForwardLights = 2048;

struct EffectDecision {
    std::string name;
    bool enabled = false;      // the switch in RenderSettings
    bool needed = false;       // the scene calls for it
    bool implemented = false;  // a pass exists for it in this build
    bool planned = false;      // enabled && needed && implemented
    std::string reason;        // "on: 5 BLEND materials", "off: no BLEND materials", ...
};


// The decision helper of every effect: `gating` false (render.gating=off) plans a switched-on
// effect even when the scene does not need it (the gating property test renders both ways).
EffectDecision decide_effect(const char* name, bool enabled, bool needed, const std::string& need_reason, bool gating);

class GpuScene;

// What an effect reads of the frame's view to decide (Effect::view_amount).
struct ViewInput {
    const Scene& scene;
    const RenderSettings& settings;
    const Camera* camera = nullptr;  // the camera the frames use, before with_lens; nullptr: the settings' lens
    const GpuScene* gpu = nullptr;   // the uploaded scene (its poses and motion); nullptr where none is (`info`)
    float aspect = 1.0f;             // the frame's width / height
};
// Each registered effect's view amount (Effect::view_amount), by effect name.
using ViewAmounts = std::map<std::string, double, std::less<>>;
ViewAmounts view_amounts(const ViewInput& in);

struct Features {
    // The registered effect modules' decisions (engine/effects/registry.cpp), in registry order.
    std::vector<EffectDecision> modules;
    LightSetup lights;  // what the light buffer holds (the effects' light_setup)
    const Scene* source = nullptr;  // the analyzed scene
    bool environment = false;  // sky pass and ambient term
    bool blended_drawn = false;  // a planned effect draws the BLEND materials (else they are drawn opaque)
    int punctual_lights = 0;
    // Point and spot lights with a range (or a reach: lights.cutoff); with two or more (and at most kMaxTiledForwardLights
    // lights in all) the forward pass culls the lights per 16x16 tile (light_tiles.comp).
    int ranged_lights = 0;
    bool forward_light_tiles = false;
    int area_light_pieces = 0;  // emissive primitives drawn * arealight.samples
    // With shadows planned: how the shadow budget shared the maps (ShadowAtlas::text); set by the
    // renderer's plan, which sees the light buffer.
    std::string shadow_budget;
    // With punctual lights: their reach and what it culls per tile at the view (LightReach::text);
    // set by the renderer every frame, for its camera and image size.
    std::string light_reach;
    bool deferred = false;      // the render path
    std::string path_reason;
    SceneFeatures scene;
    // What effects measured of the view before planning (Effect::view_estimate), by effect
    // name, when the caller could trace it (the renderer, `info`); they decide from it.
    ViewEstimates estimates;
    // The estimate the effect `name` made, or nullptr.
    const ViewEstimate* estimate(std::string_view name) const;
    // What each effect measured of the view it decides from (Effect::view_amount): the
    // renderer re-plans when one turns zero or non-zero.
    ViewAmounts view_amounts;
    // The view amount of the effect `name`; 0 when it has none.
    double view_amount(std::string_view name) const;
    std::vector<const EffectDecision*> effects() const {
        std::vector<const EffectDecision*> v;
        for (const EffectDecision& d : modules) v.push_back(&d);
        return v;
    }
    // The decision for the effect `name` (an --effects name); throws candela::Error (internal)
    // for an unknown name.
    const EffectDecision& decision(std::string_view name) const;
};

// `camera`: the camera the frames use; nullptr: the settings' lens. `amounts`: the effects' view
// amounts as the renderer measured them; nullptr: measured here from `camera`, without an uploaded
// scene.
// `estimates`: what the effects that ask for one measured of the view (Effect::view_estimate).
Features analyze(const Scene& scene, const RenderSettings& settings, const ViewEstimates* estimates = nullptr,
                 const Camera* camera = nullptr, const ViewAmounts* amounts = nullptr);
// The effects that decide from a measurement of the view with these settings (Effect::view_estimate).
std::vector<const Effect*> effects_needing_view_estimate(const RenderSettings& settings);
// Whether planning with these settings needs a GL context: a view estimate or a plan that
// depends on the device (Effect::plans_with_device).
bool planning_needs_gl(const RenderSettings& settings);
// How the frame takes its samples: what the planned effects decided (Effect::frame_sampling).
FrameSampling frame_sampling(const Features& features, const RenderSettings& settings);

// The raster passes a frame runs, in order, with the reason for each; the renderer builds its
// frame graph from exactly this list (so `candela info` shows what will run).
struct PlannedPass {
    std::string name;
    std::string why;
    const Effect* owner = nullptr;       // the effect that adds it; nullptr: a base pass (render/)
    std::vector<std::string> programs;   // catalog names the pass draws with (built at set-up)
    bool post = false;                   // added at Stage::post (reads the resolved image)
    // Runs in every sub-frame (FrameSampling::subframes), accumulating them; the other post
    // passes run after the last sub-frame only.
    bool every_subframe = false;
    // Adds the pass to the frame's graph: the renderer calls it, base and effect passes alike.
    PassWork work = {};
};
std::vector<PlannedPass> plan_passes(const Features& features, const RenderSettings& settings);
nlohmann::json to_json(const Features& features);

}  // namespace candela
