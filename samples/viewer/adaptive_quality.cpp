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

// The knob's value as the assignment's right-hand side writes it ("half", "4", "0.5").
std::string as_text(const nlohmann::json& v) { return v.is_string() ? v.get<std::string>() : v.dump(); }

// Whether `info` is lowered by its moving value from `value` (KnobInfo::moving).
bool lowered(const KnobInfo& info, const nlohmann::json& value) {
    if (info.type == "int" && value.is_number_integer()) return value.get<long long>() > std::stoll(info.moving);
    if (info.type == "float" && value.is_number()) return value.get<double>() > std::stod(info.moving);
    if (info.type == "choice" && value.is_string()) {
        const auto at = [&](const std::string& name) { return std::find(info.choices.begin(), info.choices.end(), name) - info.choices.begin(); };
        return at(value.get<std::string>()) < at(info.moving);
    }
    return false;
}

}  // namespace

std::vector<std::string> reductions(const RenderSettings& full) {
    // Each effect's knob rows say what they are while the camera moves (KnobRows::while_moving):
    // lower sample counts and resolutions of the costly passes, never a switch of an effect and
    // never a mode that selects shader code (it would build programs in the middle of a movement).
    const nlohmann::json knobs = to_json(full)["knobs"];
    std::vector<std::string> out;
    for (const KnobInfo& info : knob_infos()) {
        if (info.moving.empty()) continue;
        const auto it = knobs.find(info.name);
        if (it == knobs.end() || !lowered(info, *it)) continue;
        if (const size_t eq = info.moving_when.find('='); eq != std::string::npos) {
            const auto when = knobs.find(info.moving_when.substr(0, eq));
            if (when == knobs.end() || as_text(*when) != info.moving_when.substr(eq + 1)) continue;
        }
        out.push_back(info.name + "=" + info.moving);
    }
    return out;
}

RenderSettings reduced_settings(const RenderSettings& full) {
    RenderSettings s = full;
    for (const std::string& a : reductions(full)) apply_knob(s, a);
    return s;
}

}  // namespace candela::viewer
