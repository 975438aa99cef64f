#include "render/settings.hpp"

#include <cmath>
#include <functional>
#include <map>

#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "effects/registry.hpp"

namespace candela {
namespace {

[[noreturn]] void out_of_range(const KnobInfo& k, const std::string& value) {
    throw bad_input("--set " + k.name + "=" + value + ": expected " + k.type + " in " + k.range);
}


template <typename Get>
Knob make_int(const char* name, int lo, int hi, Get ref, const char* help) {
    KnobInfo info{name, "int", "[" + std::to_string(lo) + ", " + std::to_string(hi) + "]", help};
    return {info,
            [=](RenderSettings& s, const std::string& v) {
                try {
                    size_t used = 0;
                    const long x = std::stol(v, &used);
                    if (used == v.size() && x >= lo && x <= hi) {
                        ref(s) = static_cast<int>(x);
                        return;
                    }
                } catch (const std::exception&) {
                }
                out_of_range(info, v);
            },
            [=](const RenderSettings& s) { return nlohmann::json(ref(const_cast<RenderSettings&>(s))); }};
}

template <typename Get>
Knob make_float(const char* name, float lo, float hi, Get ref, const char* help) {
    char range[64];
    std::snprintf(range, sizeof range, "[%g, %g]", lo, hi);
    KnobInfo info{name, "float", range, help};
    return {info,
            [=](RenderSettings& s, const std::string& v) {
                try {
                    size_t used = 0;
                    const float x = std::stof(v, &used);
                    if (used == v.size() && std::isfinite(x) && x >= lo && x <= hi) {
                        ref(s) = x;
                        return;
                    }
                } catch (const std::exception&) {
                }
                out_of_range(info, v);
            },
            [=](const RenderSettings& s) { return nlohmann::json(ref(const_cast<RenderSettings&>(s))); }};
}

template <typename Get>
Knob make_bool(const char* name, Get ref, const char* help) {
    KnobInfo info{name, "bool", "0|1|true|false|on|off", help};
    return {info,
            [=](RenderSettings& s, const std::string& v) {
                if (v == "1" || v == "true" || v == "on") ref(s) = true;
                else if (v == "0" || v == "false" || v == "off") ref(s) = false;
                else out_of_range(info, v);
            },
            [=](const RenderSettings& s) { return nlohmann::json(ref(const_cast<RenderSettings&>(s))); }};
}

template <typename Get>
Knob make_choice(const char* name, std::vector<std::string> choices, Get ref, const char* help) {
    std::string range;
    for (const auto& c : choices) range += (range.empty() ? "" : "|") + c;
    KnobInfo info{name, "choice", range, help};
    return {info,
            [=](RenderSettings& s, const std::string& v) {
                for (const auto& c : choices)
                    if (c == v) {
                        ref(s) = v;
                        return;
                    }
                out_of_range(info, v);
            },
            [=](const RenderSettings& s) { return nlohmann::json(ref(const_cast<RenderSettings&>(s))); }};
}

std::vector<Knob> legacy_knobs() {
    return {
        make_bool("forward.depth_prepass", [](RenderSettings& s) -> bool& { return s.forward.depth_prepass; },
                  "draw depth first, then shade each pixel once"),
        make_choice("render.path", {"auto", "forward", "deferred"}, [](RenderSettings& s) -> std::string& { return s.path; },
                    "render path (--path); auto: deferred from deferred.auto_lights lights"),
        make_bool("render.gating", [](RenderSettings& s) -> bool& { return s.gating; },
                  "skip the effects the scene does not call for; off runs every switched-on effect (the image must not change)"),
        make_int("deferred.auto_lights", 1, 100000, [](RenderSettings& s) -> int& { return s.deferred.auto_lights; },
                 "--path auto renders deferred from this many lights (measured: see README)"),
        make_int("shadows.resolution", 64, 8192, [](RenderSettings& s) -> int& { return s.shadow.resolution; },
                 "texels per side of every shadow view"),
        make_choice("shadows.filter", {"hard", "pcf", "pcss"}, [](RenderSettings& s) -> std::string& { return s.shadow.filter; },
                    "hard: one 2x2 hardware PCF tap; pcf: pcf_size^2 taps; pcss: blocker search + variable kernel"),
        make_int("shadows.pcf_size", 1, 15, [](RenderSettings& s) -> int& { return s.shadow.pcf_size; },
                 "PCF kernel width in taps (each tap is a 2x2 hardware PCF)"),
        make_int("shadows.pcss_blocker_taps", 1, 128, [](RenderSettings& s) -> int& { return s.shadow.pcss_blocker_taps; },
                 "PCSS blocker-search taps"),
        make_int("shadows.pcss_taps", 1, 256, [](RenderSettings& s) -> int& { return s.shadow.pcss_taps; },
                 "PCSS filter taps"),
        make_float("shadows.max_radius", 1.0f, 64.0f, [](RenderSettings& s) -> float& { return s.shadow.max_radius; },
                   "largest PCSS search/filter radius in texels"),
        make_float("shadows.normal_bias", 0.0f, 16.0f, [](RenderSettings& s) -> float& { return s.shadow.normal_bias; },
                   "receiver offset along its normal, in shadow texels"),
        make_float("shadows.depth_bias", 0.0f, 16.0f, [](RenderSettings& s) -> float& { return s.shadow.depth_bias; },
                   "receiver depth moved towards the light, in shadow texels"),
        make_float("shadows.slope_bias", 0.0f, 16.0f, [](RenderSettings& s) -> float& { return s.shadow.slope_bias; },
                   "slope-scaled polygon offset factor of the caster pass"),
        make_float("shadows.receiver_slope_bias", 0.0f, 4.0f, [](RenderSettings& s) -> float& { return s.shadow.receiver_slope_bias; },
                   "extra depth bias of a filter tap r texels out: r * tan(theta) texels times this"),
        make_int("shadows.cascades", 1, 4, [](RenderSettings& s) -> int& { return s.shadow.cascades; },
                 "cascades of a directional light's shadow map"),
        make_int("shadows.max_lights", 0, 4096, [](RenderSettings& s) -> int& { return s.shadow.max_lights; },
                 "shadow-casting lights at most: directional first, then the brightest"),
        make_float("shadows.split_lambda", 0.0f, 1.0f, [](RenderSettings& s) -> float& { return s.shadow.split_lambda; },
                   "cascade split blend: 0 uniform, 1 logarithmic"),
        make_int("arealight.samples", 1, 64, [](RenderSettings& s) -> int& { return s.arealight.samples; },
                 "shadowed Lambertian pieces per emissive mesh (raster area-light approximation)"),
        make_int("rsm.resolution", 16, 4096, [](RenderSettings& s) -> int& { return s.rsm_knobs.resolution; },
                 "texels per side of each light's reflective shadow map"),
        make_int("rsm.samples", 1, 1024, [](RenderSettings& s) -> int& { return s.rsm_knobs.samples; },
                 "RSM texels gathered per pixel and light"),
        make_choice("rsm.gather", {"full", "half", "quarter"}, [](RenderSettings& s) -> std::string& { return s.rsm_knobs.gather; },
                    "resolution of the RSM gather pass"),
        make_float("rsm.radius", 1e-3f, 1.0f, [](RenderSettings& s) -> float& { return s.rsm_knobs.radius; },
                   "RSM sampling radius, as a fraction of the map's width"),
        make_int("rsm.max_lights", 1, 8, [](RenderSettings& s) -> int& { return s.rsm_knobs.max_lights; },
                 "lights with a reflective shadow map: directional first, then the brightest"),
        make_choice("debug.view", {"none", "visibility", "ao", "indirect"}, [](RenderSettings& s) -> std::string& { return s.debug.view; },
                    
                    
                    "visibility: light debug.light's visibility (0..1); ao: the SSAO buffer; indirect: RSM light; instead of radiance"),
        make_int("debug.light", 0, 1000000, [](RenderSettings& s) -> int& { return s.debug.light; },
                 "the light of debug.view=visibility; >= the punctual light count: all area lights"),
        make_float("ao.radius", 1e-6f, 1e9f, [](RenderSettings& s) -> float& { return s.ao.radius; },
                   "ambient occlusion radius in world units (SSAO and --raytrace ao)"),
        make_choice("rt.jitter", {"auto", "on", "off"}, [](RenderSettings& s) -> std::string& { return s.rt.jitter; },
                    "jittered primary rays; auto: on for path and whitted, off for the raster references"),
        make_float("rt.whitted_max_roughness", 0.0f, 1.0f, [](RenderSettings& s) -> float& { return s.rt.whitted_max_roughness; },
                   "surfaces at most this rough reflect as mirrors in whitted mode"),
        make_bool("rt.indirect_occlusion", [](RenderSettings& s) -> bool& { return s.rt.indirect_occlusion; },
                  "--raytrace indirect: 0 ignores visibility between the bounce points (RSM's own model)"),
        make_bool("rt.env_importance", [](RenderSettings& s) -> bool& { return s.rt.env_importance; },
                  "path/direct: importance-sample environment maps by luminance, with MIS"),
        make_int("environment.resolution", 16, 1024, [](RenderSettings& s) -> int& { return s.environment.resolution; },
                 "face size of the static environment map's prefiltered cube (built at start-up)"),
    };
}

// The effects not yet moved into engine/effects/ (issue 18), switched by these flags.
struct LegacyEffect {
    const char* name;
    bool RenderSettings::*flag;
};
const LegacyEffect kLegacy[] = {{"shadows", &RenderSettings::shadows},
                                {"rsm", &RenderSettings::rsm}};

}  // namespace

std::vector<EffectSlot> default_effect_slots() {
    std::vector<EffectSlot> slots;
    for (const Effect* e : effect_registry()) slots.push_back({e, e->on_by_default(), e->default_options()});
    return slots;
}

bool RenderSettings::on(std::string_view name) const {
    for (const EffectSlot& slot : effects)
        if (name == slot.effect->name()) return slot.on;
    for (const LegacyEffect& l : kLegacy)
        if (name == l.name) return this->*l.flag;
    throw Error(ExitCode::internal, "RenderSettings: no effect named '" + std::string(name) + "'");
}

void RenderSettings::set_on(std::string_view name, bool value) {
    for (EffectSlot& slot : effects)
        if (name == slot.effect->name()) {
            slot.on = value;
            return;
        }
    for (const LegacyEffect& l : kLegacy)
        if (name == l.name) {
            this->*l.flag = value;
            return;
        }
    throw Error(ExitCode::internal, "RenderSettings: no effect named '" + std::string(name) + "'");
}

const std::vector<Knob>& knobs() {
    static const std::vector<Knob> all = [] {
        std::vector<Knob> rows = legacy_knobs();
        for (const Effect* e : effect_registry())
            for (Knob& k : e->knobs()) rows.push_back(std::move(k));
        return rows;
    }();
    return all;
}

const std::vector<std::string>& effect_names() {
    static const std::vector<std::string> names = [] {
        std::vector<std::string> v;
        for (const LegacyEffect& l : kLegacy) v.push_back(l.name);
        for (const Effect* e : effect_registry()) v.push_back(e->name());
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

const std::vector<KnobInfo>& knob_infos() {
    static const std::vector<KnobInfo> infos = [] {
        std::vector<KnobInfo> v;
        for (const Knob& k : knobs()) v.push_back(k.info);
        return v;
    }();
    return infos;
}

nlohmann::json to_json(const RenderSettings& s) {
    nlohmann::json j;
    for (const std::string& n : effect_names()) j["effects"][n] = s.on(n);
    for (const Knob& k : knobs()) j["knobs"][k.info.name] = k.get(s);
    return j;
}

}  // namespace candela
