#include "render/settings.hpp"

#include <cmath>
#include <functional>
#include <map>
#include <set>

#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "render/effect_registry.hpp"
#include "scene/scene.hpp"

namespace candela {
namespace {

// The base settings (render/): path, gating, debug views, AO radius, the tracer, the environment.
std::vector<Knob> base_knobs() {
    using S = RenderSettings;
    std::vector<Knob> rows;
    auto add = [&](std::vector<Knob> more) {
        for (Knob& k : more) rows.push_back(std::move(k));
    };
    add(KnobRows<S>("render", [](S& s) -> S& { return s; })
            .choice("path", &S::path, kRenderPaths, "render path (--path); auto: deferred from deferred.auto_lights lights")
            .boolean("gating", &S::gating,
                     "skip the effects the scene does not call for; off runs every switched-on effect (the image must not change)")
            .boolean("material_layers", &S::material_layers,
                     "shade the material extensions' layers (clearcoat, sheen, anisotropy, iridescence, unlit, their textures); "
                     "off: the base BRDF only, cheaper (the tracer keeps them)")
            .rows);
    add(KnobRows<S::Forward>("forward", [](S& s) -> S::Forward& { return s.forward; })
            .boolean("depth_prepass", &S::Forward::depth_prepass, "draw depth first, then shade each pixel once")
            .boolean("light_tiles", &S::Forward::light_tiles,
                     "cull the point and spot lights by their reach (range or lights.cutoff) per 16x16 tile before shading (the same image, "
                     "faster with many)")
            .rows);
    add(KnobRows<S::Lights>("lights", [](S& s) -> S::Lights& { return s.lights; })
            .real("cutoff", &S::Lights::cutoff, 0.0f, 1e6f,
                  "point/spot lights without a range stop where their light falls below this fraction of the darkest display step "
                  "(exposure 0); 0: unbounded")
            .rows);
    add(KnobRows<S::Deferred>("deferred", [](S& s) -> S::Deferred& { return s.deferred; })
            .integer("auto_lights", &S::Deferred::auto_lights, 1, 100000, "--path auto renders deferred from this many lights (measured: see README)")
            .rows);
    add(KnobRows<S::Debug>("debug", [](S& s) -> S::Debug& { return s.debug; })
            .choice("view", &S::Debug::view, kDebugViews,
                    "instead of radiance: visibility: light debug.light's visibility (0..1); ao: the occlusion of ambient light (SSAO); indirect: the indirect light (GI probes, RSM)")
            .integer("light", &S::Debug::light, 0, 1000000, "the light of debug.view=visibility; >= the punctual light count: all area lights")
            .rows);
    add(KnobRows<S::AmbientOcclusion>("ao", [](S& s) -> S::AmbientOcclusion& { return s.ao; })
            .real("radius", &S::AmbientOcclusion::radius, 1e-6f, 1e9f, "ambient occlusion radius in world units (SSAO and --raytrace ao)")
            .rows);
    add(KnobRows<S::RayTracing>("rt", [](S& s) -> S::RayTracing& { return s.rt; })
            .choice("jitter", &S::RayTracing::jitter, kRtJitters, "camera rays at random points of the pixel (its box-filtered average; auto = on, every mode) or off: through its centre, as the rasterizer samples")
            .real("whitted_max_roughness", &S::RayTracing::whitted_max_roughness, 0.0f, 1.0f,
                  "surfaces at most this rough reflect as mirrors in whitted mode")
            .boolean("indirect_occlusion", &S::RayTracing::indirect_occlusion,
                     "--raytrace indirect: 0 ignores visibility between the bounce points (RSM's own model)")
            .boolean("env_importance", &S::RayTracing::env_importance, "path/direct: importance-sample environment maps by luminance, with MIS")
            .integer("shutter_slices", &S::RayTracing::shutter_slices, 0, 1 << 24,
                     "motion blur: poses (and BVH builds) per render at random shutter times; 0: one per sample")
            .rows);
    add(KnobRows<S::EnvironmentMap>("environment", [](S& s) -> S::EnvironmentMap& { return s.environment; })
            .integer("resolution", &S::EnvironmentMap::resolution, 16, 1024,
                     "face size of the static environment map's prefiltered cube (built at start-up)")
            .rows);
    add(KnobRows<S::Lens>("camera", [](S& s) -> S::Lens& { return s.camera; })
            .real("aperture", &S::Lens::aperture, -1.0f, 1e9f,
                  "thin-lens radius in scene units (depth of field); 0: pinhole; -1: the camera's own (glTF extras.aperture)")
            .real("focus_distance", &S::Lens::focus_distance, -1.0f, 1e9f,
                  "distance in focus along the view axis, scene units; 0: auto; -1: the camera's own (extras.focus_distance)")
            .real("shutter", &S::Lens::shutter, 0.0f, 1.0f, "motion blur: shutter open for this fraction of a frame, centred on the frame's time; 0: off")
            .real("fps", &S::Lens::fps, 1.0f, 1000.0f, "frames per second: the frame length camera.shutter is a fraction of")
            .rows);
    return rows;
}

}  // namespace

std::vector<EffectSlot> default_effect_slots() {
    std::vector<EffectSlot> slots;
    for (const Effect* e : effect_registry()) slots.push_back({e, e->on_by_default(), e->default_options()});
    return slots;
}

bool RenderSettings::on(std::string_view name) const {
    for (const EffectSlot& slot : effects)
        if (name == slot.effect->name()) return slot.on;
    throw Error(ExitCode::internal, "RenderSettings: no effect named '" + std::string(name) + "'");
}

void RenderSettings::set_on(std::string_view name, bool value) {
    for (EffectSlot& slot : effects)
        if (name == slot.effect->name()) {
            slot.on = value;
            return;
        }
    throw Error(ExitCode::internal, "RenderSettings: no effect named '" + std::string(name) + "'");
}

const std::vector<Knob>& knobs() {
    static const std::vector<Knob> all = [] {
        std::vector<Knob> rows = base_knobs();
        for (const Effect* e : effect_registry())
            for (Knob& k : e->knobs()) rows.push_back(std::move(k));
        return rows;
    }();
    return all;
}

const std::vector<std::string>& effect_names() {
    static const std::vector<std::string> names = [] {
        std::vector<std::string> v;
        for (const Effect* e : effect_registry())
            if (e->switchable()) v.push_back(e->name());
        return v;
    }();
    return names;
}

void apply_effects(RenderSettings& s, const std::string& list) {
    if (list == "all" || list == "none") {
        for (const std::string& n : effect_names()) s.set_on(n, list == "all");
        return;
    }
    for (const std::string& n : effect_names()) s.set_on(n, false);
    size_t start = 0;
    while (start <= list.size()) {
        const size_t comma = list.find(',', start);
        const std::string name = list.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
        bool found = false;
        for (const std::string& n : effect_names())
            if (n == name) {
                s.set_on(n, true);
                found = true;
            }
        if (!found)
            if (const Effect* e = find_effect(name); e && !e->switchable())
            {
                std::string groups;
                for (const std::string& g : e->knob_groups()) groups += (groups.empty() ? "" : ", ") + g + ".*";
                throw bad_input("--effects: '" + name + "' is not switched with --effects: it runs whenever the scene or its knobs call "
                                "for it (candela info lists it under 'planned by the scene or their knobs'; its knobs: " + groups + ")");
            }
        if (!found) {
            std::string known;
            for (const auto& n : effect_names()) known += (known.empty() ? "" : ", ") + n;
            throw bad_input("--effects: unknown effect '" + name + "' (all, none, or a comma list of: " + known + ")");
        }
        if (comma == std::string::npos) break;
        start = comma + 1;
    }
}

void apply_knob(RenderSettings& s, const std::string& assignment) {
    const size_t eq = assignment.find('=');
    if (eq == std::string::npos) throw bad_input("--set '" + assignment + "': expected KNOB=VALUE");
    const std::string name = assignment.substr(0, eq), value = assignment.substr(eq + 1);
    for (const Knob& k : knobs())
        if (k.info.name == name) {
            k.set(s, value);
            return;
        }
    std::string known;
    for (const Knob& k : knobs()) known += "\n  " + k.info.name + " (" + k.info.type + " " + k.info.range + ")";
    throw bad_input("--set: unknown knob '" + name + "'; knobs are:" + known);
}

void apply_knobs(RenderSettings& s, const std::vector<std::string>& assignments) {
    std::set<std::string> given;
    for (const std::string& a : assignments) {
        apply_knob(s, a);
        given.insert(a.substr(0, a.find('=')));
    }
    for (const Effect* e : effect_registry()) e->complete_knobs(s, given);
}

const std::vector<KnobInfo>& knob_infos() {
    static const std::vector<KnobInfo> infos = [] {
        std::vector<KnobInfo> v;
        for (const Knob& k : knobs()) v.push_back(k.info);
        return v;
    }();
    return infos;
}

Camera with_lens(Camera camera, const RenderSettings& s) {
    if (s.camera.aperture >= 0.0f) camera.aperture = s.camera.aperture;
    if (s.camera.focus_distance >= 0.0f) camera.focus_distance = s.camera.focus_distance;
    return camera;
}

nlohmann::json to_json(const RenderSettings& s) {
    nlohmann::json j;
    for (const std::string& n : effect_names()) j["effects"][n] = s.on(n);
    for (const Knob& k : knobs()) j["knobs"][k.info.name] = k.get(s);
    return j;
}

}  // namespace candela
