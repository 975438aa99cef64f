// The viewer's ImGui panel, docked at the window's right edge: settings, knobs, the error budget,
// the reference mode, animation, status.
#include "viewer_internal.hpp"

#include <algorithm>
#include <cstdio>

#include "rt/tracer_options.hpp"
#include "render/program_catalog.hpp"

namespace candela::viewer {
namespace {

// Dim text that wraps at the panel's edge (ImGui::TextDisabled does not wrap).
void wrapped_disabled(const std::string& text) {
    ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyleColorVec4(ImGuiCol_TextDisabled));
    ImGui::TextWrapped("%s", text.c_str());
    ImGui::PopStyleColor();
}

}  // namespace

void Viewer::knob_widgets(const std::string& prefix, bool exclude) {
    const nlohmann::json values = to_json(settings_)["knobs"];
    for (const KnobInfo& k : knob_infos()) {
        const bool match = k.name.rfind(prefix, 0) == 0;
        if (match == exclude) continue;
        const nlohmann::json& v = values[k.name];
        std::string assignment;
        ImGui::PushID(k.name.c_str());
        if (k.type == "bool") {
            bool b = v.get<bool>();
            if (ImGui::Checkbox(k.name.c_str(), &b)) assignment = k.name + "=" + (b ? "1" : "0");
        } else if (k.type == "int") {
            int i = v.get<int>();
            if (ImGui::InputInt(k.name.c_str(), &i, 1, 8, ImGuiInputTextFlags_EnterReturnsTrue)) assignment = k.name + "=" + std::to_string(i);
        } else if (k.type == "float") {
            float f = v.get<float>();
            if (ImGui::InputFloat(k.name.c_str(), &f, 0.0f, 0.0f, "%.4g", ImGuiInputTextFlags_EnterReturnsTrue))
                assignment = k.name + "=" + std::to_string(f);
        } else {
            const std::string current = v.get<std::string>();
            if (ImGui::BeginCombo(k.name.c_str(), current.c_str())) {
                size_t start = 0;
                while (start <= k.range.size()) {
                    const size_t bar = k.range.find('|', start);
                    const std::string choice = k.range.substr(start, bar == std::string::npos ? std::string::npos : bar - start);
                    if (ImGui::Selectable(choice.c_str(), choice == current)) assignment = k.name + "=" + choice;
                    if (bar == std::string::npos) break;
                    start = bar + 1;
                }
                ImGui::EndCombo();
            }
        }
        if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s\n%s %s", k.help.c_str(), k.type.c_str(), k.range.c_str());
        ImGui::PopID();
        if (!assignment.empty()) {
            RenderSettings s = settings_;
            try {
                apply_knob(s, assignment);
                apply_settings(s);
            } catch (const Error& e) {
                settings_error_ = e.what();
            }
        }
    }
}

void Viewer::animation_ui() {
    Playback& a = anim_;
    char label[160];
    const auto item = [&](int i) {
        if (i < 0) return animation_label(i);
        std::snprintf(label, sizeof label, "%s (%.2f s)", animation_label(i).c_str(), scene_.animations[static_cast<size_t>(i)].end);
        return std::string(label);
    };
    if (ImGui::BeginCombo("animation", item(a.animation).c_str())) {
        for (int i = -1; i < static_cast<int>(scene_.animations.size()); ++i) {
            ImGui::PushID(i);
            if (ImGui::Selectable(item(i).c_str(), i == a.animation) && i != a.animation) {
                const bool was_playing = a.playing;
                a.select(i, i >= 0 ? scene_.animations[static_cast<size_t>(i)].end : 0.0f);
                if (i >= 0 && was_playing) a.play();
            }
            ImGui::PopID();
        }
        ImGui::EndCombo();
    }
    if (a.animation < 0) {
        wrapped_disabled("the rest pose: the file's node transforms, default morph weights, skins at their bind pose");
        return;
    }
    if (ImGui::Button(a.playing ? "pause" : "play", ImVec2(ImGui::GetFrameHeight() * 3.0f, 0.0f))) a.playing ? a.pause() : a.play();
    ImGui::SameLine();
    ImGui::Checkbox("loop", &a.loop);
    ImGui::SameLine();
    ImGui::Text("%.3f / %.3f s", a.time, a.duration);
    // Scrubbing: the slider sets the time; playing goes on from there (pause first to hold it).
    float t = a.time;
    std::snprintf(label, sizeof label, "%%.3f s of %.3f", a.duration);
    if (ImGui::SliderFloat("time", &t, 0.0f, a.duration, label)) a.set_time(t);
    float speed = a.speed;
    if (ImGui::SliderFloat("speed", &speed, Playback::kMinSpeed, Playback::kMaxSpeed, "%.2fx", ImGuiSliderFlags_Logarithmic))
        a.set_speed(speed);
    // The shutter (camera.shutter, also under Knobs): motion blur in the raster frame (when the
    // effect plans) and in the reference.
    float shutter = settings_.camera.shutter;
    if (ImGui::SliderFloat("shutter", &shutter, 0.0f, 1.0f, "%.2f frame")) {
        RenderSettings s = settings_;
        s.camera.shutter = shutter;
        apply_settings(s);
    }
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("camera.shutter: the fraction of a frame (camera.fps) the shutter is open; 0: no motion blur");
    std::string info;
    if (!pose_ms_.empty()) {
        std::snprintf(label, sizeof label, "last pose %.2f ms (CPU pose, upload%s); %zu poses", pose_ms_.back(),
                      shutter_.instant() ? "" : ", shutter motion", pose_ms_.size());
        info = label;
    }
    if (!shutter_.instant()) {
        std::snprintf(label, sizeof label, "; shutter open %.4f..%.4f s at %.0f fps", shutter_.open, shutter_.close, settings_.camera.fps);
        info += label;
    }
    if (!info.empty()) wrapped_disabled(info);
}

void Viewer::variant_ui() {
    auto label = [&](int i) {
        return i < 0 ? std::string("default (the file's materials)")
                     : std::to_string(i) + ": " + scene_.variants[static_cast<size_t>(i)] + " (" +
                           std::to_string(variant_changes(scene_, i)) + " primitives)";
    };
    if (ImGui::BeginCombo("variant", label(scene_.active_variant).c_str())) {
        for (int i = -1; i < static_cast<int>(scene_.variants.size()); ++i) {
            ImGui::PushID(i);
            if (ImGui::Selectable(label(i).c_str(), i == scene_.active_variant)) select_variant_live(i);
            ImGui::PopID();
        }
        ImGui::EndCombo();
    }
}

void Viewer::adaptive_ui() {
    bool on = adaptive_.enabled();
    if (ImGui::Checkbox("adaptive quality", &on)) {
        adaptive_.set_enabled(on);
        force_reduced_ = false;
    }
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("while the view moves, render cheaper frames (lower effect rates, then a smaller size, upscaled);\n"
                          "when it has been still for %.2f s, one full-quality frame, shown until the view changes",
                          adaptive_.params().still_seconds);
    float target = static_cast<float>(adaptive_.target_ms());
    if (ImGui::SliderFloat("target ms", &target, 10.0f, 1000.0f, "%.0f ms", ImGuiSliderFlags_Logarithmic)) adaptive_.set_target_ms(target);
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("a moving frame should take at most this long (100 ms: 10 fps)");
    const int w = std::max(render_w_, 1), h = std::max(render_h_, 1);
    ImGui::Text("level %s%s, scale %.2f (%dx%d)", quality_level_name(quality_.level), force_reduced_ ? " (forced)" : "", quality_.scale, w, h);
    if (last_render_frame_ms_ >= 0.0)
        ImGui::Text("last rendered frame %.1f ms (%.1f fps), target %.0f ms", last_render_frame_ms_, 1000.0 / std::max(last_render_frame_ms_, 1e-3),
                    adaptive_.target_ms());
    wrapped_disabled("while moving: " + join_reductions());
}

void Viewer::budget_ui() {
    const ImVec4 warm(0.95f, 0.75f, 0.35f, 1.0f);
    bool on = budget_.on() || budget_pending_;
    if (ImGui::Checkbox("choose the settings for E", &on)) {
        if (on) budget_pending_ = true;
        else budget_off();
    }
    if (ImGui::IsItemHovered())
        ImGui::SetTooltip("the cheapest candidate of the ladder whose predicted error against the path tracer is at most E\n"
                          "(mean display difference over 4x4 blocks) becomes the settings; off gives back the settings from before");
    float e = static_cast<float>(budget_e_);
    ImGui::SliderFloat("E", &e, 0.001f, 1.0f, "%.4g", ImGuiSliderFlags_Logarithmic);
    if (std::isfinite(e)) budget_e_ = std::clamp(static_cast<double>(e), 0.001, 1.0);
    // A new E chooses again when the slider is let go (each choice traces the statistics).
    if (ImGui::IsItemDeactivatedAfterEdit() && budget_.on() && budget_e_ != budget_.budget()) budget_pending_ = true;
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("0.01: about 2.5/255 of display value per channel; 0.1: a difference anyone sees");
    if (!budget_.on()) {
        ImGui::BeginDisabled();
        ImGui::Button("re-choose for this view");
        ImGui::EndDisabled();
        return;
    }
    if (ImGui::Button("re-choose for this view")) budget_pending_ = true;
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("the choice reads the statistics of the view it was made from; camera moves do not choose again");
    if (!budget_.choice()) return;
    const budget::Choice& c = *budget_.choice();
    const auto name = [](const budget::Prediction& p) { return budget::ladder()[static_cast<size_t>(p.candidate)].name; };
    const budget::Prediction& chosen = c.predictions[static_cast<size_t>(c.chosen)];
    if (c.trace) {
        ImGui::TextColored(warm, "chosen: the path tracer");
        ImGui::TextWrapped("The frame is traced: no raster candidate is predicted within E = %.4g. The reference mode (path) refines "
                           "the view between frames%s.",
                           budget_.budget(), ref_.tracer ? "" : " (starting)");
        if (ref_.on && ref_.tracer) ImGui::Text("reference: %d spp", ref_.tracer->progressive_samples());
        ImGui::Text("runner-up: %s, predicted error %.4f, time x%.2f", name(chosen).c_str(), chosen.error, chosen.time);
        wrapped_disabled("the most accurate raster candidate (its predicted error is above E); the raster frame under the reference renders at it");
    } else {
        ImGui::TextColored(ImVec4(0.45f, 0.85f, 0.45f, 1.0f), "chosen: %s", name(chosen).c_str());
        if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", budget::ladder()[static_cast<size_t>(chosen.candidate)].summary().c_str());
        ImGui::Text("predicted error %.4f (E %.4g), time x%.2f speed of light", chosen.error, budget_.budget(), chosen.time);
        if (c.runner_up >= 0) {
            const budget::Prediction& r = c.predictions[static_cast<size_t>(c.runner_up)];
            ImGui::Text("runner-up: %s, predicted error %.4f, time x%.2f", name(r).c_str(), r.error, r.time);
            wrapped_disabled("rejected: its predicted error is above E");
        } else {
            ImGui::TextUnformatted("runner-up: none (no cheaper candidate)");
        }
    }
    wrapped_disabled(budget_stats_ + ". Knob and effect edits apply over the choice until the next one.");
}

void Viewer::draw_ui(double frame_ms) {
    // Docked: pinned to the right edge at full height, opaque (the scene is not behind it), and
    // resizable only by its left edge; the new width moves the scene's edge on the next frame.
    const ImVec2 display = ImGui::GetIO().DisplaySize;
    const float width = panel_width(display.x);
    ImGui::SetNextWindowPos(ImVec2(display.x - width, 0.0f), ImGuiCond_Always);
    ImGui::SetNextWindowSize(ImVec2(width, display.y), ImGuiCond_Always);
    ImGui::SetNextWindowSizeConstraints(ImVec2(std::min(kMinPanelWidth, width), display.y),
                                        ImVec2(std::max(width, display.x - kMinSceneWidth), display.y));
    ImGui::PushStyleColor(ImGuiCol_WindowBg, ImVec4(0.08f, 0.08f, 0.09f, 1.0f));
    ImGui::PushStyleVar(ImGuiStyleVar_WindowRounding, 0.0f);
    ImGui::Begin("Candela", nullptr, ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoCollapse | ImGuiWindowFlags_NoTitleBar);
    ImGui::PopStyleVar();
    ImGui::PopStyleColor();
    if (ImGui::GetWindowWidth() != width) panel_width_ = ImGui::GetWindowWidth();  // dragged by the user
    ImGui::TextWrapped("%s", ctx_.device_string().c_str());
    frame_times_.push_back(frame_ms);
    if (frame_times_.size() > 60) frame_times_.pop_front();
    std::vector<double> sorted(frame_times_.begin(), frame_times_.end());
    std::sort(sorted.begin(), sorted.end());
    ImGui::Text("frame %.1f ms (median of %zu)  %s", sorted[sorted.size() / 2], sorted.size(), controller_.fly_mode ? "fly" : "orbit");
    if (!o_.lighting.reason.empty()) ImGui::TextWrapped("lighting: %s", o_.lighting.reason.c_str());
    ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyleColorVec4(ImGuiCol_TextDisabled));
    ImGui::TextWrapped("drag: turn  shift/middle drag: pan  wheel: zoom  WASDQE: move  F: frame  Tab: fly  P: screenshot  "
                       "H: hide this panel%s", scene_.animations.empty() ? "" : "  Space: play/pause  arrows: step a frame");
    ImGui::PopStyleColor();
    if (!shader_errors_.empty()) {
        ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1.0f, 0.45f, 0.4f, 1.0f));
        ImGui::TextWrapped("Shader error (the last good program is in use):\n%s", shader_errors_.c_str());
        ImGui::PopStyleColor();
    }
    if (!settings_error_.empty()) {
        ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1.0f, 0.45f, 0.4f, 1.0f));
        ImGui::TextWrapped("%s", settings_error_.c_str());
        ImGui::PopStyleColor();
    }
    if (!status_.empty()) wrapped_disabled(status_);

    if (ImGui::CollapsingHeader("Adaptive quality", ImGuiTreeNodeFlags_DefaultOpen)) adaptive_ui();
    if (ImGui::CollapsingHeader("Error budget", budget_.on() ? ImGuiTreeNodeFlags_DefaultOpen : 0)) budget_ui();
    if (ImGui::CollapsingHeader("Camera")) {
        if (ImGui::Button("Frame scene (F)")) controller_.frame(bounds_);
        for (size_t i = 0; i < scene_.cameras.size(); ++i) {
            ImGui::SameLine();
            const std::string label = scene_.cameras[i].name.empty() ? "camera " + std::to_string(i) : scene_.cameras[i].name;
            if (ImGui::Button(label.c_str())) select_camera(std::to_string(i));
        }
        ImGui::SliderFloat("exposure (EV)", &o_.exposure_ev, -8.0f, 8.0f);
    }
    if (!scene_.animations.empty() && ImGui::CollapsingHeader("Animation", ImGuiTreeNodeFlags_DefaultOpen)) animation_ui();
    if (!scene_.variants.empty() && ImGui::CollapsingHeader("Material variants", ImGuiTreeNodeFlags_DefaultOpen)) variant_ui();
    if (ImGui::CollapsingHeader("Effects", ImGuiTreeNodeFlags_DefaultOpen)) {
        const Features& f = renderer_.features();
        RenderSettings s = settings_;
        bool changed = false;
        // The checkbox is the user's switch (--effects); beside it, what the planner made of it,
        // and below it the planner's reason, wrapped to the panel. The status column starts
        // after the longest effect name.
        float name_width = 0.0f;
        for (const std::string& n : effect_names()) name_width = std::max(name_width, ImGui::CalcTextSize(n.c_str()).x);
        const ImGuiStyle& style = ImGui::GetStyle();
        const float status_x = style.WindowPadding.x + ImGui::GetFrameHeight() + style.ItemInnerSpacing.x + name_width + style.ItemSpacing.x * 2.0f;
        for (const std::string& name : effect_names()) {
            bool on = s.on(name);
            const EffectStatus status = effect_status(on, f.decision(name));
            if (ImGui::Checkbox(name.c_str(), &on)) {
                s.set_on(name, on);
                changed = true;
            }
            if (ImGui::IsItemHovered())
                ImGui::SetTooltip("switch %s on or off (--effects); the planner still skips it when the scene does not need it",
                                  name.c_str());
            ImGui::SameLine(status_x);
            const ImVec4 colour = status.state == EffectState::running   ? ImVec4(0.45f, 0.85f, 0.45f, 1.0f)
                                  : status.state == EffectState::skipped ? ImVec4(0.95f, 0.75f, 0.35f, 1.0f)
                                                                         : ImGui::GetStyleColorVec4(ImGuiCol_TextDisabled);
            ImGui::TextColored(colour, "%s", status.label.c_str());
            ImGui::Indent(ImGui::GetFrameHeightWithSpacing());
            wrapped_disabled(status.detail);
            // Under shadows: how many lights the shadow budget shadowed, at what resolution, and
            // how many it left out.
            if (name == "shadows" && !f.shadow_budget.empty()) wrapped_disabled("shadow budget: " + f.shadow_budget);
            // And the lights' reach: how many the tiles cull.
            if (name == "shadows" && !f.light_reach.empty()) wrapped_disabled("light reach: " + f.light_reach);
            // An effect that converges over frames says how far it has got (GI's probes).
            if (const EffectProgress p = renderer_.effect_progress(name); p.active && !p.line.empty()) {
                const ImVec4 c = p.converged ? ImVec4(0.45f, 0.85f, 0.45f, 1.0f) : ImVec4(0.95f, 0.75f, 0.35f, 1.0f);
                ImGui::PushStyleColor(ImGuiCol_Text, c);
                ImGui::TextWrapped("%s", p.line.c_str());
                ImGui::PopStyleColor();
            }
            ImGui::Unindent(ImGui::GetFrameHeightWithSpacing());
        }
        // The effects the scene and their knobs plan (not --effects switches): whether the
        // emitters are lights or emission only, and why, as `info` lists them.
        for (const EffectDecision& d : f.modules) {
            if (std::find(effect_names().begin(), effect_names().end(), d.name) != effect_names().end()) continue;
            ImGui::TextColored(d.planned ? ImVec4(0.45f, 0.85f, 0.45f, 1.0f) : ImGui::GetStyleColorVec4(ImGuiCol_TextDisabled), "%s",
                               d.name.c_str());  // the reason starts with on: or off:
            ImGui::Indent(ImGui::GetFrameHeightWithSpacing());
            wrapped_disabled(d.reason);
            ImGui::Unindent(ImGui::GetFrameHeightWithSpacing());
        }
        if (changed) apply_settings(s);
    }
    if (ImGui::CollapsingHeader("Reference (ray tracer)", ref_.on ? ImGuiTreeNodeFlags_DefaultOpen : 0)) {
        Reference& r = ref_;
        ImGui::Checkbox("refine in the background", &r.on);
        ImGui::Combo("mode", &r.mode, Reference::kModes, 4);
        ImGui::Combo("show", &r.view, Reference::kViews, 5);
        ImGui::SliderFloat("ms per frame", &r.budget_ms, 5.0f, 500.0f, "%.0f");
        if (r.on && r.tracer) {
            ImGui::Text("%d spp", r.tracer->progressive_samples());
            if (r.rmse >= 0.0) {
                ImGui::SameLine();
                ImGui::Text("RMSE vs reference: %.4f linear, %.4f display", r.rmse, r.rmse_display);
            }
        }
    }
    if (ImGui::CollapsingHeader("Knobs")) knob_widgets("debug.", true);
    if (ImGui::CollapsingHeader("Debug views")) {
        knob_widgets("debug.", false);
        const std::string current = inspect_.name.empty() ? "(final image)" : inspect_.name;
        if (ImGui::BeginCombo("buffer", current.c_str())) {
            if (ImGui::Selectable("(final image)", inspect_.name.empty())) inspect_.name.clear();
            for (const std::string& n : renderer_.inspectable())
                if (ImGui::Selectable(n.c_str(), n == inspect_.name)) inspect_.name = n;
            ImGui::EndCombo();
        }
        if (!inspect_.name.empty()) {
            static const char* channels[] = {"rgb", "r", "g", "b", "a"};
            ImGui::Combo("channel", &inspect_.channel, channels, 5);
            ImGui::SliderFloat("scale", &inspect_.scale, 0.01f, 100.0f, "%.3g", ImGuiSliderFlags_Logarithmic);
            ImGui::InputInt("layer / probe", &inspect_.layer);
            inspect_.layer = std::max(inspect_.layer, 0);
            ImGui::SliderFloat("mip level", &inspect_.lod, 0.0f, 8.0f, "%.1f");
            ImGui::TextDisabled("depth is reversed-Z (near 1, far 0); cubes show longitude/latitude");
        }
        renderer_.set_inspect(inspect_.name);
    }
    if (ImGui::CollapsingHeader("Passes", ImGuiTreeNodeFlags_DefaultOpen)) {
        const FrameReport& r = renderer_.last_frame();
        if (ImGui::BeginTable("passes", 5, ImGuiTableFlags_RowBg | ImGuiTableFlags_SizingStretchProp)) {
            for (const char* h : {"pass", "GPU ms", "draws", "triangles", "dispatches"}) ImGui::TableSetupColumn(h);
            ImGui::TableHeadersRow();
            for (const PassStats& p : r.passes) {
                ImGui::TableNextRow();
                ImGui::TableNextColumn();
                ImGui::TextUnformatted(p.name.c_str());
                ImGui::TableNextColumn();
                if (p.gpu_ms >= 0.0) ImGui::Text("%.2f", p.gpu_ms);
                else ImGui::TextDisabled("-");
                ImGui::TableNextColumn();
                ImGui::Text("%d", p.counters.draw_calls);
                ImGui::TableNextColumn();
                ImGui::Text("%zu", p.counters.triangles);
                ImGui::TableNextColumn();
                ImGui::Text("%d", p.counters.dispatches);
            }
            ImGui::EndTable();
        }
        for (const auto& [name, why] : r.culled) wrapped_disabled("culled " + name + ": " + why);
        if (ImGui::TreeNode("planned passes and why")) {
            for (const PlannedPass& p : plan_passes(renderer_.features(), settings_)) {
                ImGui::Bullet();
                ImGui::TextWrapped("%s: %s", p.name.c_str(), p.why.c_str());
            }
            ImGui::TreePop();
        }
    }
    ImGui::End();
}

}  // namespace candela::viewer
