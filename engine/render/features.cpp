#include "render/features.hpp"

#include <algorithm>

#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "render/effect_registry.hpp"
#include "render/passes/pass_env.hpp"

namespace candela {
namespace {

// `gating` false (render.gating=off) plans a switched-on effect even when the scene does not need
// it: the property test renders both ways and expects the same image.
EffectDecision decide(const char* name, bool enabled, bool needed, bool implemented, const std::string& need_reason,
                      bool gating) {
    EffectDecision d;
    d.name = name;
    d.enabled = enabled;
    d.needed = needed;
    d.implemented = implemented;
    d.planned = enabled && (needed || !gating) && implemented;
    if (!needed && d.planned) d.reason = "on: render.gating=off (not called for: " + need_reason + ")";
    else if (!needed) d.reason = "off: " + need_reason;
    else if (!enabled) d.reason = "off: switched off (--effects); the scene has " + need_reason;
    else if (!implemented) d.reason = "off: the scene has " + need_reason + ", but no pass implements it yet";
    else d.reason = "on: " + need_reason;
    return d;
}

}  // namespace

EffectDecision decide_effect(const char* name, bool enabled, bool needed, const std::string& need_reason, bool gating) {
    return decide(name, enabled, needed, true, need_reason, gating);
}

const EffectDecision& Features::decision(std::string_view name) const {
    for (const EffectDecision* d : effects())
        if (d->name == name) return *d;
    throw Error(ExitCode::internal, "no effect named '" + std::string(name) + "'");
}

const ViewEstimate* Features::estimate(std::string_view name) const {
    const auto it = estimates.find(std::string(name));
    return it == estimates.end() ? nullptr : &it->second;
}

std::vector<const Effect*> effects_needing_view_estimate(const RenderSettings& s) {
    std::vector<const Effect*> out;
    for (const Effect* e : effect_registry())
        if (e->view_estimate(s)) out.push_back(e);
    return out;
}

bool planning_needs_gl(const RenderSettings& s) {
    for (const Effect* e : effect_registry())
        if (e->view_estimate(s) || e->plans_with_device(s)) return true;
    return false;
}

FrameSampling frame_sampling(const Features& f, const RenderSettings& s) {
    FrameSampling out;
    for (size_t i = 0; i < effect_registry().size(); ++i)
        if (f.modules[i].planned) effect_registry()[i]->frame_sampling(f, s, out);
    return out;
}

ViewAmounts view_amounts(const ViewInput& in) {
    ViewAmounts out;
    for (const Effect* e : effect_registry()) out.emplace(e->name(), e->view_amount(in));
    return out;
}

double Features::view_amount(std::string_view name) const {
    const auto it = view_amounts.find(name);
    return it != view_amounts.end() ? it->second : 0.0;
}

Features analyze(const Scene& scene, const RenderSettings& s, const ViewEstimates* estimates, const Camera* camera, const ViewAmounts* amounts) {
    Features f;
    f.source = &scene;
    f.view_amounts = amounts ? *amounts : view_amounts({scene, s, camera, nullptr, 1.0f});
    if (estimates) f.estimates = *estimates;
    f.scene = analyze_features(scene);
    f.environment = scene.environment.present();
    f.punctual_lights = static_cast<int>(scene.placed_lights().size());
    for (const auto& placed : scene.placed_lights())
        f.ranged_lights += (placed.light->type == LightType::point || placed.light->type == LightType::spot) &&
                           (placed.light->range > 0.0f || s.lights.cutoff > 0.0f);
    const SceneFeatures& sf = f.scene;
    // The effect modules decide in registry order (an effect may read the decisions before it),
    // then say what the light buffer holds (LightSetup).
    for (const Effect* e : effect_registry()) {
        f.modules.push_back(e->decide(f, s));
        if (f.modules.back().planned && e->draws_blended_surfaces()) f.blended_drawn = true;
    }
    f.lights.cutoff = s.lights.cutoff;
    for (size_t i = 0; i < effect_registry().size(); ++i) effect_registry()[i]->light_setup(s, f.modules[i], f.lights);
    f.area_light_pieces = sf.emissive_primitives * f.lights.area_samples;
    const int light_count = f.punctual_lights + f.area_light_pieces;
    if (s.path != RenderPath::automatic) {
        f.deferred = s.path == RenderPath::deferred;
        f.path_reason = std::string("--path ") + choice_name(kRenderPaths, s.path);
    } else {
        f.deferred = light_count >= s.deferred.auto_lights;
        f.path_reason = "auto: " + std::to_string(light_count) + " light(s) " + (f.deferred ? ">= " : "< ") +
                        std::to_string(s.deferred.auto_lights) + " (deferred.auto_lights)";
    }
    f.forward_light_tiles = !f.deferred && s.forward.light_tiles && f.ranged_lights >= 2 && light_count <= kMaxTiledForwardLights;
    return f;
}

namespace {
// A base pass (render/passes/) with the usual arguments.
PassWork base_pass(void (*add)(FrameGraph&, const PassEnv&, FrameTargets&)) {
    return [add](const PassSite& p) { add(p.graph, p.env, p.targets); };
}
// ... and one that draws BLEND geometry as opaque unless a planned effect draws it blended.
PassWork base_pass(void (*add)(FrameGraph&, const PassEnv&, FrameTargets&, bool), bool blended_drawn) {
    return [add, blended_drawn](const PassSite& p) { add(p.graph, p.env, p.targets, !blended_drawn); };
}
// ... and the forward pass, which may cull its lights per tile.
PassWork base_pass(void (*add)(FrameGraph&, const PassEnv&, FrameTargets&, bool, bool), bool blended_drawn, bool tiles) {
    return [add, blended_drawn, tiles](const PassSite& p) { add(p.graph, p.env, p.targets, !blended_drawn, tiles); };
}
}  // namespace

std::vector<PlannedPass> plan_passes(const Features& f, const RenderSettings& s) {
    std::vector<PlannedPass> plan;
    // The passes the planned effect modules add at `stage`, in registry order.
    auto add_stage = [&](Stage stage) {
        for (size_t i = 0; i < effect_registry().size(); ++i)
            if (f.modules[i].planned) effect_registry()[i]->plan(stage, f, s, plan);
    };
    add_stage(Stage::light_views);
    const std::string what = f.blended_drawn ? "opaque and masked geometry"
                             : f.scene.transparency.needed ? "all geometry (BLEND drawn as opaque: no planned effect draws it)"
                                                     : "all geometry";
    // The planned module that reads depth and normals before shading (forward path: a prepass).
    const char* screen_reader = nullptr;
    for (size_t i = 0; i < effect_registry().size() && !screen_reader; ++i)
        if (f.modules[i].planned) screen_reader = effect_registry()[i]->needs_depth_normals();
    if (f.deferred) {
        plan.push_back({"gbuffer", what + "; deferred path, " + f.path_reason, nullptr, {"gbuffer"}, false, false,
                        base_pass(add_gbuffer_pass, f.blended_drawn)});
        // A multisampled G-buffer (FrameSampling::samples): the screen-space effects read sample
        // 0's depth and normal; the lighting shades edge pixels once per surface they show.
        const bool ms = frame_sampling(f, s).samples > 1;
        if (ms)
            plan.push_back({"gbuffer_resolve", "multisampled G-buffer: single-sample depth and normals for the screen passes",
                            nullptr, {"gbuffer_resolve"}, false, false, base_pass(add_gbuffer_resolve_pass)});
        add_stage(Stage::screen);
        plan.push_back({"deferred_lighting",
                        ms ? "tiled light culling and shading of the G-buffer; edge pixels once per surface their samples show"
                           : "tiled light culling and shading of the G-buffer",
                        nullptr, ms ? std::vector<std::string>{"deferred_light_ms", "deferred_light_ms_edges"}
                                    : std::vector<std::string>{"deferred_light"},
                        false, false, base_pass(add_deferred_lighting_pass)});
        add_stage(Stage::after_lighting);
    } else {
        if (screen_reader)
            plan.push_back({"depth_normal_prepass", std::string(screen_reader) + " needs depth and normals before shading", nullptr,
                            {"depth_normals"}, false, false, base_pass(add_depth_normal_prepass, f.blended_drawn)});
        else if (s.forward.depth_prepass)
            plan.push_back({"depth_prepass", "forward.depth_prepass=1", nullptr, {"depth_prepass", "depth_prepass_mask"}, false, false,
                            base_pass(add_depth_prepass)});
        add_stage(Stage::screen);
        if (f.forward_light_tiles)
            plan.push_back({"forward_opaque",
                            what + "; forward path, " + f.path_reason + "; lights culled per 16x16 tile (" +
                                std::to_string(f.ranged_lights) + " with a range)",
                            nullptr, {"forward", "light_tiles"}, false, false, base_pass(add_forward_opaque_pass, f.blended_drawn, true)});
        else
            plan.push_back({"forward_opaque", what + "; forward path, " + f.path_reason, nullptr, {"forward"}, false, false,
                            base_pass(add_forward_opaque_pass, f.blended_drawn, false)});
        add_stage(Stage::after_lighting);
    }
    if (f.environment) plan.push_back({"sky", "the scene has environment light", nullptr, {"sky"}, false, false, base_pass(add_sky_pass)});
    add_stage(Stage::blended);
    const size_t before_post = plan.size();
    add_stage(Stage::post);
    for (size_t i = before_post; i < plan.size(); ++i) plan[i].post = true;
    return plan;
}

nlohmann::json to_json(const Features& f) {
    nlohmann::json j;
    for (const EffectDecision* d : f.effects())
        j["effects"][d->name] = {{"enabled", d->enabled}, {"needed", d->needed}, {"planned", d->planned}, {"reason", d->reason}};
    j["environment"] = f.environment;
    j["punctual_lights"] = f.punctual_lights;
    j["area_light_pieces"] = f.area_light_pieces;
    if (!f.shadow_budget.empty()) j["shadow_budget"] = f.shadow_budget;
    if (!f.light_reach.empty()) j["light_reach"] = f.light_reach;
    j["path"] = f.deferred ? "deferred" : "forward";
    j["path_reason"] = f.path_reason;
    j["emissive_area_lights"] = f.scene.emissive_area_lights.needed;
    j["transmission"] = f.scene.transmission.needed;
    for (const Effect* e : effect_registry())
        if (const ViewEstimate* v = f.estimate(e->name())) e->estimate_json(*v, j);
    return j;
}

}  // namespace candela
