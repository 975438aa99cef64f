// The viewer's animation clock (samples/viewer/playback.hpp): playing advances by
// dt * speed and wraps or stops at the end, scrubbing clamps, and the scene is posed again only
// when the animation, its time or the shutter changed (paused: no work).
#include <gtest/gtest.h>

#include <cmath>

#include "../../samples/viewer/playback.hpp"

namespace candela::viewer {
namespace {

Playback playing(float duration) {
    Playback p;
    p.select(0, duration);
    p.play();
    return p;
}

TEST(ViewerPlayback, LoopsOverTheDurationAtTheSpeed) {
    Playback p = playing(2.0f);
    p.advance(0.5f);
    EXPECT_FLOAT_EQ(p.time, 0.5f);
    p.set_speed(2.0f);
    p.advance(0.5f);
    EXPECT_FLOAT_EQ(p.time, 1.5f);
    p.advance(0.5f);  // 2.5 s wraps to 0.5 s
    EXPECT_NEAR(p.time, 0.5f, 1e-6f);
    EXPECT_TRUE(p.playing);
    p.set_speed(100.0f);  // clamped to the slider's range
    EXPECT_FLOAT_EQ(p.speed, Playback::kMaxSpeed);
    p.set_speed(0.0f);
    EXPECT_FLOAT_EQ(p.speed, Playback::kMinSpeed);
}

TEST(ViewerPlayback, WithoutLoopStopsAtTheEndAndPlayStartsOver) {
    Playback p = playing(1.0f);
    p.loop = false;
    p.advance(0.75f);
    p.advance(0.75f);
    EXPECT_FLOAT_EQ(p.time, 1.0f);
    EXPECT_FALSE(p.playing);
    p.play();
    EXPECT_FLOAT_EQ(p.time, 0.0f);
    EXPECT_TRUE(p.playing);
}

TEST(ViewerPlayback, PausedDoesNoWorkAndScrubbingPosesOnce) {
    Playback p = playing(1.0f);
    EXPECT_TRUE(p.needs_pose(0.0f, 30.0f));  // never posed
    p.mark_posed(0.0f, 30.0f);
    EXPECT_FALSE(p.needs_pose(0.0f, 30.0f));
    p.advance(0.1f);
    EXPECT_TRUE(p.needs_pose(0.0f, 30.0f));
    p.mark_posed(0.0f, 30.0f);
    p.pause();
    for (int i = 0; i < 10; ++i) {
        p.advance(0.1f);
        EXPECT_FALSE(p.needs_pose(0.0f, 30.0f)) << "frame " << i;
    }
    EXPECT_NEAR(p.time, 0.1f, 1e-6f);
    p.set_time(0.6f);  // scrub
    EXPECT_TRUE(p.needs_pose(0.0f, 30.0f));
    p.mark_posed(0.0f, 30.0f);
    p.set_time(0.6f);  // the same time again: nothing to do
    EXPECT_FALSE(p.needs_pose(0.0f, 30.0f));
    EXPECT_FALSE(p.playing);  // scrubbing keeps it paused
    // A new shutter or frame rate changes the motion, so the pose (its motion) is redone.
    EXPECT_TRUE(p.needs_pose(0.5f, 30.0f));
    EXPECT_TRUE(p.needs_pose(0.0f, 24.0f));
}

TEST(ViewerPlayback, ScrubClampsAndIgnoresNonFiniteTimes) {
    Playback p = playing(3.0f);
    p.set_time(5.0f);
    EXPECT_FLOAT_EQ(p.time, 3.0f);
    p.set_time(-1.0f);
    EXPECT_FLOAT_EQ(p.time, 0.0f);
    p.set_time(1.25f);
    p.set_time(std::nanf(""));
    EXPECT_FLOAT_EQ(p.time, 1.25f);
}

TEST(ViewerPlayback, NoneIsTheRestPoseAndDoesNotPlay) {
    Playback p = playing(2.0f);
    p.advance(0.5f);
    p.select(-1, 0.0f);
    EXPECT_FALSE(p.playing);
    EXPECT_FLOAT_EQ(p.time, 0.0f);
    p.play();  // nothing to play
    EXPECT_FALSE(p.playing);
    EXPECT_TRUE(p.needs_pose(0.0f, 30.0f));  // the rest pose is posed once
    p.mark_posed(0.0f, 30.0f);
    EXPECT_FALSE(p.needs_pose(0.5f, 30.0f));  // the shutter cannot move the rest pose
    // Choosing an animation again starts at 0 and poses.
    p.select(1, 2.0f);
    EXPECT_TRUE(p.needs_pose(0.5f, 30.0f));
    // A single-keyframe animation (duration 0) stays at 0 while playing.
    p.select(2, 0.0f);
    p.play();
    p.advance(0.3f);
    EXPECT_FLOAT_EQ(p.time, 0.0f);
}

}  // namespace
}  // namespace candela::viewer
