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

#include "effects/gi/gi.hpp"
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

// GI probes in the viewer: a still converges them before its frame (gi.budget 0);
// the viewer spreads their updates over frames so that the first frame and every frame after a
// change stay interactive. 16384 rays per frame is 256 probes of 64 rays (the default; 128 of 128):
// whole 64-probe batches of the GI pass, so the updates happen in the same batches as in a still
// and the converged image equals `candela render`'s. Measured on llvmpipe, 2 shared cores, cornell_point (README,
// viewer section).
constexpr int kViewerGiBudget = 16384;

// Whether the --set assignments (as given on the command line) set `knob`.
inline bool sets_knob(const std::vector<std::string>& assignments, std::string_view knob) {
    for (const std::string& a : assignments) {
        const std::string_view name = std::string_view(a).substr(0, a.find('='));
        if (name == knob) return true;
    }
    return false;
}

// The viewer's settings: gi.budget = kViewerGiBudget unless the user's --set gave one (0 there
// means: converge before each frame, as a still does).
inline void apply_viewer_defaults(RenderSettings& s, const std::vector<std::string>& set_knobs) {
    if (!sets_knob(set_knobs, "gi.budget")) s.get<GiOptions>().budget = kViewerGiBudget;
}

// The panel's GI line (and the log's, when it changes): how far the probes are and at what
// budget. Empty when the probes are not planned: the effect row says why.
inline std::string gi_status_line(const GiStatus& st, int budget) {
    if (!st.planned) return {};
    char head[128];
    std::snprintf(head, sizeof head, "GI probes %dx%dx%d, %d rays, %d bounce(s): ", st.counts.x, st.counts.y, st.counts.z,
                  st.rays, st.bounces);
    std::string line = head;
    if (st.converged()) {
        line += "converged (" + std::to_string(st.updates_planned) + " updates";
        line += budget > 0 ? ")" : ", before the frame: gi.budget=0)";
    } else {
        // Rays still owed, and the frames they take at this budget (the current update's
        // finished part is not known here: an upper bound).
        const long long per_update = static_cast<long long>(st.counts.x) * st.counts.y * st.counts.z * st.rays;
        const long long owed = static_cast<long long>(st.updates_planned - st.updates_done) * per_update;
        line += std::to_string(st.updates_done) + "/" + std::to_string(st.updates_planned) + " updates done (converging, ";
        if (budget > 0) {
            const long long per_frame = std::max<long long>(budget, st.rays);
            line += std::to_string(budget) + " rays/frame, <= " + std::to_string((owed + per_frame - 1) / per_frame) + " frames to go)";
        } else {
            line += "gi.budget=0: the next frame)";
        }
    }
    if (st.nonfinite > 0) line += "; " + std::to_string(st.nonfinite) + " non-finite ray results replaced by 0";
    return line;
}

}  // namespace candela::viewer
