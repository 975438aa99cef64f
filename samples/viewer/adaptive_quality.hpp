#pragma once
// Adaptive quality in the viewer: while the view moves (camera input, a script's camera
// commands, an animation playing) the viewer renders cheaper frames, and when the view has been
// still for a moment it renders one frame at full quality and keeps showing it.
//
// The levels, cheapest last, form a ladder of steps:
//   full      the user's settings at the scene's full size (the view is still)
//   reduced   reduced_settings(): lower rates of the costly knobs, full size (step 0)
//   scaled    reduced settings at a fraction of the size, upscaled with linear filtering
//             (steps 1.. : AdaptiveParams::scales)
// While moving, each measured frame time moves the step: above the target, down to the first
// step whose predicted time (scaled by the pixel count) meets it; up one step only after
// `up_frames` frames whose prediction for the step above stays under target * up_margin and
// under what that step was measured at earlier in the same movement. A frame time near the
// target therefore settles on one step instead of alternating. A new movement starts at the
// step the last one ended on.
//
// The class is plain logic (no GL, no clock of its own): the viewer passes the time.
#include <string>
#include <vector>

#include "render/settings.hpp"

namespace candela::viewer {

enum class QualityLevel { full, reduced, scaled };
const char* quality_level_name(QualityLevel level);

struct QualityState {
    QualityLevel level = QualityLevel::full;
    float scale = 1.0f;  // of the scene's width and height
    int step = -1;       // on the ladder; -1: full
    bool operator==(const QualityState&) const = default;
};

struct AdaptiveParams {
    double target_ms = 100.0;     // a moving frame should take at most this long (10 fps)
    double still_seconds = 0.25;  // no movement for this long: the full-quality frame
    // The ladder's scales: the first is the reduced level at full size (1), the others the scaled
    // steps, decreasing. At least one entry; each in (0, 1].
    // The last, a quarter of each side, is what keeps full-screen scenes near 10 fps on a 2-core
    // CPU rasteriser (docs/performance.md).
    std::vector<float> scales = {1.0f, 0.71f, 0.5f, 0.35f, 0.25f};
    double up_margin = 0.75;  // step up when the step above is predicted under target * this
    int up_frames = 2;        // ... for this many frames in a row
};

class AdaptiveQuality {
public:
    explicit AdaptiveQuality(AdaptiveParams params = {});

    // Off: every frame is full quality (update() returns full), and the movement is forgotten.
    void set_enabled(bool on);
    bool enabled() const { return enabled_; }
    // The target frame time in ms, clamped to [1, 10000]; a value that is not finite is ignored.
    void set_target_ms(double ms);
    double target_ms() const { return params_.target_ms; }
    const AdaptiveParams& params() const { return params_; }

    // Once per frame before it is rendered: whether the view changed this frame, and the time in
    // seconds on any steady clock. Returns the state to render this frame at.
    QualityState update(bool moved, double now_seconds);
    // The measured time (ms) of the frame rendered at the state update() last returned. Only
    // frames rendered while moving steer the ladder; negative or non-finite times are ignored.
    void measured(double frame_ms);

    const QualityState& state() const { return state_; }
    bool moving() const { return moving_; }
    // Steps taken (down or up) since construction: the tests count oscillation with it.
    int step_changes() const { return step_changes_; }

private:
    QualityState state_at(int step) const;
    void set_step(int step);

    AdaptiveParams params_;
    bool enabled_ = true;
    bool moving_ = false;
    double last_move_ = 0.0;
    int step_ = 0;               // the step a moving frame renders at
    int fast_frames_ = 0;        // frames in a row that would allow a step up
    std::vector<double> seen_;   // the last time measured at each step in this movement (< 0: none)
    QualityState state_;
    int step_changes_ = 0;
};

// The knob assignments that make `full` cheaper for moving frames: lower sample and tap counts,
// coarser gathers, a smaller GI ray budget. Each assignment lowers its knob (a knob that is
// already as low or lower is left out), so the list is empty only when nothing is left to lower.
// Changing these knobs re-plans the renderer but builds no new shader program and starts no
// converging effect over (GI keeps its probes: only gi.budget changes).
std::vector<std::string> reductions(const RenderSettings& full);
// `full` with reductions(full) applied.
RenderSettings reduced_settings(const RenderSettings& full);

}  // namespace candela::viewer
