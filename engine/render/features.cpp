#include "render/features.hpp"

#include <nlohmann/json.hpp>

namespace candela {
namespace {

EffectDecision decide(const char* name, bool enabled, bool needed, bool implemented, const std::string& need_reason) {
    EffectDecision d;
    d.name = name;
    d.enabled = enabled;
    d.needed = needed;
    d.implemented = implemented;
    d.planned = enabled && needed && implemented;
    if (!needed) d.reason = "off: " + need_reason;
    else if (!enabled) d.reason = "off: switched off (--effects); the scene has " + need_reason;
    else if (!implemented) d.reason = "off: the scene has " + need_reason + ", but no pass implements it yet";
    else d.reason = "on: " + need_reason;
    return d;
}

}  // namespace

Features analyze(const Scene& scene, const RenderSettings& s) {
    Features f;
    f.scene = analyze_features(scene, s.reflections_knobs.max_roughness);
    f.environment = scene.environment.present();
    f.punctual_lights = static_cast<int>(scene.placed_lights().size());
    const SceneFeatures& sf = f.scene;
    f.shadows = decide("shadows", s.shadows, sf.shadows.needed, false, sf.shadows.reason);
    f.ssao = decide("ssao", s.ssao, f.environment, false,
                    f.environment ? "ambient/environment light to occlude" : "no ambient or environment light to occlude");
    bool shadowed_light = false;
    for (const auto& pl : scene.placed_lights())
        shadowed_light = shadowed_light || pl.light->type != LightType::point;
    const bool rsm_needed = sf.shadows.needed && shadowed_light;
    f.rsm = decide("rsm", s.rsm, rsm_needed, false,
                   rsm_needed ? "a shadowed directional or spot light" : "no shadowed directional or spot light");
    f.transparency = decide("transparency", s.transparency, sf.transparency.needed, true, sf.transparency.reason);
    f.reflections = decide("reflections", s.reflections, sf.reflections.needed, false, sf.reflections.reason);
    return f;
}

std::vector<PlannedPass> plan_passes(const Features& f, const RenderSettings& s) {
    std::vector<PlannedPass> plan;
    if (s.forward.depth_prepass) plan.push_back({"depth_prepass", "forward.depth_prepass=1"});
    plan.push_back({"forward_opaque", f.transparency.planned ? "opaque and masked geometry"
                                      : f.transparency.needed ? "all geometry (BLEND drawn as opaque: transparency off)"
                                                              : "all geometry"});
    if (f.environment) plan.push_back({"sky", "the scene has environment light"});
    if (f.transparency.planned) plan.push_back({"transparent", f.transparency.reason.substr(4)});
    return plan;
}

nlohmann::json to_json(const Features& f) {
    nlohmann::json j;
    for (const EffectDecision* d : f.effects())
        j["effects"][d->name] = {{"enabled", d->enabled}, {"needed", d->needed}, {"planned", d->planned}, {"reason", d->reason}};
    j["environment"] = f.environment;
    j["punctual_lights"] = f.punctual_lights;
    j["emissive_area_lights"] = f.scene.emissive_area_lights.needed;
    j["transmission"] = f.scene.transmission.needed;
    return j;
}

}  // namespace candela
