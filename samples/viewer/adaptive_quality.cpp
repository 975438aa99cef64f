#include "adaptive_quality.hpp"

#include <algorithm>
#include <cmath>

#include <nlohmann/json.hpp>

namespace candela::viewer {

const char* quality_level_name(QualityLevel level) {
    switch (level) {
        case QualityLevel::full: return "full";
        case QualityLevel::reduced: return "reduced";
        case QualityLevel::scaled: return "scaled";
    }
    return "full";
}

AdaptiveQuality::AdaptiveQuality(AdaptiveParams params) : params_(std::move(params)) {
    // A ladder the class can work with whatever it was given: scales in (0, 1], decreasing,
    // starting at 1 (the reduced level renders at full size).
    std::vector<float> scales{1.0f};
    for (float s : params_.scales)
        if (std::isfinite(s) && s > 0.0f && s < scales.back()) scales.push_back(s);
    params_.scales = scales;
    if (!std::isfinite(params_.still_seconds) || params_.still_seconds < 0.0) params_.still_seconds = 0.25;
    if (!std::isfinite(params_.up_margin) || params_.up_margin <= 0.0 || params_.up_margin > 1.0) params_.up_margin = 0.75;
    params_.up_frames = std::max(params_.up_frames, 1);
    const double target = params_.target_ms;
    params_.target_ms = 100.0;
    set_target_ms(target);
    seen_.assign(params_.scales.size(), -1.0);
}

void AdaptiveQuality::set_enabled(bool on) {
    enabled_ = on;
    if (!on) {
        moving_ = false;
        state_ = QualityState{};
    }
}

void AdaptiveQuality::set_target_ms(double ms) {
    if (!std::isfinite(ms)) return;
    params_.target_ms = std::clamp(ms, 1.0, 10000.0);
}

QualityState AdaptiveQuality::state_at(int step) const {
    QualityState s;
    s.step = step;
    s.scale = params_.scales[static_cast<size_t>(step)];
    s.level = step == 0 ? QualityLevel::reduced : QualityLevel::scaled;
    return s;
}

void AdaptiveQuality::set_step(int step) {
    step = std::clamp(step, 0, static_cast<int>(params_.scales.size()) - 1);
    if (step != step_) ++step_changes_;
    step_ = step;
    fast_frames_ = 0;
}

QualityState AdaptiveQuality::update(bool moved, double now_seconds) {
    if (!enabled_) return state_ = QualityState{};
    if (moved) {
        if (!moving_) std::fill(seen_.begin(), seen_.end(), -1.0);  // a new movement: measure afresh
        moving_ = true;
        last_move_ = now_seconds;
    } else if (moving_ && !(now_seconds - last_move_ < params_.still_seconds)) {
        moving_ = false;  // still long enough (or the clock is unusable): full quality
    }
    state_ = moving_ ? state_at(step_) : QualityState{};
    return state_;
}

void AdaptiveQuality::measured(double frame_ms) {
    if (!enabled_ || state_.step < 0 || !std::isfinite(frame_ms) || frame_ms < 0.0) return;
    const int at = state_.step;
    seen_[static_cast<size_t>(at)] = frame_ms;
    const double target = params_.target_ms;
    const auto predicted = [&](int to) {
        const double r = static_cast<double>(params_.scales[static_cast<size_t>(to)]) / static_cast<double>(params_.scales[static_cast<size_t>(at)]);
        return frame_ms * r * r;  // the cost in proportion to the pixels
    };
    const int last = static_cast<int>(params_.scales.size()) - 1;
    if (frame_ms > target) {
        int to = at + 1;
        while (to < last && predicted(to) > target) ++to;
        set_step(std::min(to, last));
        return;
    }
    if (at == 0) {
        fast_frames_ = 0;
        return;
    }
    // Up only when the step above is expected to stay well under the target, and was not seen
    // slower than that earlier in this movement (the prediction ignores fixed costs).
    const double above = std::max(predicted(at - 1), seen_[static_cast<size_t>(at - 1)]);
    if (above < target * params_.up_margin) {
        if (++fast_frames_ >= params_.up_frames) set_step(at - 1);
    } else {
        fast_frames_ = 0;
    }
}

namespace {

// One knob lowered to at most `low` (integers) when it is above it.
void lower_int(const nlohmann::json& knobs, const char* name, int low, std::vector<std::string>& out) {
    const auto it = knobs.find(name);
    if (it == knobs.end() || !it->is_number_integer()) return;
    if (it->get<int>() > low) out.push_back(std::string(name) + "=" + std::to_string(low));
}

// A choice knob moved to `to` when its current value is one of `from`.
void lower_choice(const nlohmann::json& knobs, const char* name, std::initializer_list<const char*> from, const char* to,
                  std::vector<std::string>& out) {
    const auto it = knobs.find(name);
    if (it == knobs.end() || !it->is_string()) return;
    for (const char* f : from)
        if (it->get<std::string>() == f) out.push_back(std::string(name) + "=" + to);
}

}  // namespace

std::vector<std::string> reductions(const RenderSettings& full) {
    const nlohmann::json knobs = to_json(full)["knobs"];
    std::vector<std::string> out;
    // Screen-space ambient occlusion: half the resolution, fewer directions, a shorter blur.
    lower_choice(knobs, "ssao.resolution", {"full"}, "half", out);
    lower_int(knobs, "ssao.samples", 6, out);
    lower_int(knobs, "ssao.blur", 2, out);
    // RSM indirect light: the gather at a quarter of the resolution, fewer texels per pixel.
    lower_choice(knobs, "rsm.gather", {"full", "half"}, "quarter", out);
    lower_int(knobs, "rsm.samples", 16, out);
    // Soft shadows: fewer PCSS taps, a smaller PCF kernel (the filter mode stays: it selects the
    // shaders' code, and another mode would build programs in the middle of a movement).
    lower_int(knobs, "shadows.pcss_taps", 8, out);
    lower_int(knobs, "shadows.pcss_blocker_taps", 4, out);
    lower_int(knobs, "shadows.pcf_size", 3, out);
    // Converging GI probes: fewer rays per frame while moving (0, converge before the frame, is
    // the user's explicit choice and stays).
    if (const auto it = knobs.find("gi.budget"); it != knobs.end() && it->is_number_integer() && it->get<int>() > 4096)
        out.push_back("gi.budget=4096");
    // Lens and motion effects, and depth peeling: fewer samples and layers.
    lower_int(knobs, "dof.samples", 8, out);
    lower_int(knobs, "motion_blur.samples", 5, out);
    if (const auto it = knobs.find("transparency.mode"); it != knobs.end() && *it == "peeling") lower_int(knobs, "transparency.layers", 4, out);
    return out;
}

RenderSettings reduced_settings(const RenderSettings& full) {
    RenderSettings s = full;
    for (const std::string& a : reductions(full)) apply_knob(s, a);
    return s;
}

}  // namespace candela::viewer
