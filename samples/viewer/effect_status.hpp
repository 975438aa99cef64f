#pragma once
// What the viewer's panel says next to an effect's checkbox. The checkbox is the user's switch
// (RenderSettings, --effects); the planner's decision (EffectDecision) may still skip the effect.
// The status names the outcome in words that agree with the checkbox: a ticked box never stands
// beside "off", only beside "running" or "skipped: <why>"; an unticked one says "switched off"
// (and whether the scene would have needed it).
#include <algorithm>
#include <cstdio>
#include <string>
#include <string_view>
#include <vector>

#include "render/effect_registry.hpp"
#include "render/features.hpp"
#include "render/settings.hpp"

namespace candela::viewer {

enum class EffectState { running, skipped, switched_off };

struct EffectStatus {
    EffectState state = EffectState::switched_off;
    std::string label;   // short, beside the checkbox: "running", "skipped: not needed", "switched off"
    std::string detail;  // the planner's reason, without its "on: "/"off: " prefix (wrapped below)
};

// The planner's reason without the prefixes that repeat what the label says.
inline std::string reason_detail(std::string_view reason) {
    for (std::string_view prefix : {"on: ", "off: ", "switched off (--effects); "})
        if (reason.substr(0, prefix.size()) == prefix) reason.remove_prefix(prefix.size());
    return std::string(reason);
}

// `switch_on`: the checkbox (the user's switch); `d`: the planner's decision for the same effect.
// A debug view can force an effect on or off whatever the switch says; that is named too.
inline EffectStatus effect_status(bool switch_on, const EffectDecision& d) {
    EffectStatus s;
    const std::string why = reason_detail(d.reason);
    if (d.planned) {
        s.state = EffectState::running;
        s.label = switch_on ? "running" : "running: a debug view needs it";
        s.detail = why;
    } else if (!switch_on) {
        s.state = EffectState::switched_off;
        s.label = "switched off";
        s.detail = d.needed ? why + " (it would run)" : "not needed either: " + why;
    } else if (!d.enabled) {
        s.state = EffectState::skipped;
        s.label = "skipped: a debug view is shown";
        s.detail = why;
    } else if (!d.needed) {
        s.state = EffectState::skipped;
        s.label = "skipped: not needed";
        s.detail = why;
    } else {
        s.state = EffectState::skipped;
        s.label = "skipped: not implemented";
        s.detail = why;
    }
    return s;
}

// Whether the --set assignments (as given on the command line) set `knob`.
inline bool sets_knob(const std::vector<std::string>& assignments, std::string_view knob) {
    for (const std::string& a : assignments) {
        const std::string_view name = std::string_view(a).substr(0, a.find('='));
        if (name == knob) return true;
    }
    return false;
}

// The viewer's settings: every effect's interactive defaults (Effect::interactive_defaults, e.g.
// GI's rays per frame), each unless the user's --set gave that knob.
inline void apply_viewer_defaults(RenderSettings& s, const std::vector<std::string>& set_knobs) {
    for (const Effect* e : effect_registry())
        for (const std::string& a : e->interactive_defaults())
            if (!sets_knob(set_knobs, std::string_view(a).substr(0, a.find('=')))) apply_knob(s, a);
}

}  // namespace candela::viewer
