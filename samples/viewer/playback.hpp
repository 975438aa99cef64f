#pragma once
// The viewer's animation clock: which animation plays, where its time is, and whether
// the scene must be posed again this frame. Pure logic (no GL), so the unit tests drive it
// (tests/viewer/test_playback.cpp); viewer.cpp poses the scene when needs_pose() says so.
//
// Time runs over [0, end] (glTF keyframe times start at 0; Animation::end is the duration).
// Playing adds dt * speed each frame; at the end it wraps (loop) or stops at the end and pauses.
// Scrubbing (set_time) clamps into [0, end] and keeps playing or paused as it was.
#include <algorithm>
#include <cmath>
#include <limits>

namespace candela::viewer {

struct Playback {
    int animation = -1;     // -1: none (the rest pose)
    float duration = 0.0f;  // of `animation` (Animation::end); 0 for none
    float time = 0.0f;      // seconds, in [0, duration]
    float speed = 1.0f;     // [kMinSpeed, kMaxSpeed]
    bool playing = false;
    bool loop = true;
    static constexpr float kMinSpeed = 0.1f, kMaxSpeed = 4.0f;

    // Chooses an animation (-1: none) of the given duration; time goes back to 0.
    void select(int index, float animation_duration) {
        animation = index;
        duration = index >= 0 ? std::max(animation_duration, 0.0f) : 0.0f;
        time = 0.0f;
        if (index < 0) playing = false;
    }
    void set_time(float t) {
        if (!std::isfinite(t)) return;
        time = std::clamp(t, 0.0f, duration);
    }
    void set_speed(float s) {
        if (std::isfinite(s)) speed = std::clamp(s, kMinSpeed, kMaxSpeed);
    }
    void play() {
        if (animation < 0) return;
        // Play at the end of a non-looping animation starts it over.
        if (!loop && time >= duration) time = 0.0f;
        playing = true;
    }
    void pause() { playing = false; }

    // One frame of `dt` seconds of wall time.
    void advance(float dt) {
        if (!playing || animation < 0 || !(dt > 0.0f)) return;
        if (!(duration > 0.0f)) {  // a single keyframe: nothing moves
            time = 0.0f;
            return;
        }
        time += dt * speed;
        if (time <= duration) return;
        if (loop) {
            time = std::fmod(time, duration);
        } else {
            time = duration;
            playing = false;
        }
    }

    // Whether the pose (animation, time, and the shutter that shapes the motion) differs from the
    // one last posed; mark_posed() records the current one.
    bool needs_pose(float shutter, float fps) const {
        return animation != posed_animation_ || time != posed_time_ ||
               (animation >= 0 && (shutter != posed_shutter_ || fps != posed_fps_));
    }
    void mark_posed(float shutter, float fps) {
        posed_animation_ = animation;
        posed_time_ = time;
        posed_shutter_ = shutter;
        posed_fps_ = fps;
    }
    // Forgets the last pose: the next needs_pose() is true (e.g. at start).
    void invalidate() { posed_animation_ = -2; }

private:
    int posed_animation_ = -2;  // -2: never posed
    float posed_time_ = std::numeric_limits<float>::quiet_NaN();
    float posed_shutter_ = -1.0f, posed_fps_ = -1.0f;
};

}  // namespace candela::viewer
