#include "effects/area_lights/area_lights.hpp"

#include "effects/area_lights/area_lights_sweep.hpp"
#include "render/features.hpp"

namespace candela {
namespace {

class NoPasses final : public EffectRuntime {
public:
    void add_pass(const std::string&, FrameGraph&, const PassEnv&, FrameTargets&) override {}
};

class AreaLights final : public Effect {
public:
    const char* name() const override { return "area_lights"; }
    bool switchable() const override { return false; }
    std::any default_options() const override { return AreaLightsOptions{}; }
    std::vector<Knob> knobs() const override {
        return KnobRows<AreaLightsOptions>("arealight", [](RenderSettings& s) -> AreaLightsOptions& { return s.get<AreaLightsOptions>(); })
            .integer("samples", &AreaLightsOptions::samples, 1, 64, "shadowed Lambertian pieces per emissive mesh (raster area-light approximation)")
            .rows;
    }
    std::vector<std::string> knob_groups() const override { return {"arealight"}; }
    EffectDecision decide(const Features& f, const RenderSettings& s) const override {
        return decide_effect(name(), true, f.scene.emissive_area_lights.needed, f.scene.emissive_area_lights.reason, s.gating);
    }
    void plan(Stage, const Features&, const RenderSettings&, std::vector<PlannedPass>&) const override {}
    // The pieces are in the light buffer whether or not the scene has emitters (none then).
    void light_setup(const RenderSettings& s, const EffectDecision&, LightSetup& out) const override {
        out.area_samples = s.get<AreaLightsOptions>().samples;
    }
    std::unique_ptr<EffectRuntime> create_runtime() const override { return std::make_unique<NoPasses>(); }
    std::vector<AccuracySweep> accuracy_sweeps(bool quick) const override { return area_lights_accuracy_sweeps(quick); }
};

}  // namespace

const Effect& area_lights_effect() {
    static const AreaLights effect;
    return effect;
}

}  // namespace candela
