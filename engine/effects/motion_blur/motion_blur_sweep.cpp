#include "effects/motion_blur/motion_blur_sweep.hpp"

#include <string>

#include "render/features.hpp"
#include "scene/scene.hpp"

namespace candela {

std::vector<AccuracySweep> motion_blur_accuracy_sweeps(bool quick) {
    AccuracySweep s;
    s.effect = "motion_blur";
    s.scene = "generated:motion";
    s.buffer = AccuracySweep::Buffer::radiance;
    // Time: the whole frame, so that the row without motion blur, which runs none of the effect's
    // passes, has one too; the effect's cost is the difference to that row.
    s.own_passes = {};
    // Pixel centres (jitter 0) as the rasterizer samples them, every sample at its own time in the
    // shutter (rt.shutter_slices 0): the error is the blur's, not the edges' aliasing.
    AccuracySweep::Reference ref{rt::Mode::direct, quick ? 64 : 256};
    ref.jitter = 0;
    s.reference = ref;
    s.compared = "radiance vs `--raytrace direct` with the shutter open (camera.shutter=1 at 30 fps: each sample pass poses the scene "
                 "at its own random time in the shutter and rebuilds the tracer's geometry), pixel centres; the scene at animation 0's "
                 "midpoint (the bench's rule for animated scenes). The last row is the raster image without motion blur (the "
                 "sharp frame at the shutter's centre) against the same reference. Times are whole frames: the effect's cost is a "
                 "row's time minus that row's";
    s.reading = "The filter sees one layer: where a moving object uncovers the background, the background is guessed from the "
                "pixels beside it along the motion; a blur longer than max_radius is clamped (the object's trail is too short); "
                "rotation is approximated by each pixel's straight motion between open and close; shadows and lighting "
                "that move with the object are not blurred (the ground is static, so its shadow stays sharp). Fewer taps add "
                "noise along the motion.";
    const std::string shutter = "camera.shutter=1";
    const std::vector<int> samples = quick ? std::vector<int>{7, 15} : std::vector<int>{7, 15, 31};
    for (int n : samples)
        s.variants.push_back({std::to_string(n) + " samples", "shadows,motion_blur", {shutter, "motion_blur.samples=" + std::to_string(n)}});
    // A clamp below the fast box's motion (about 12 pixels from centre to end at 320 x 240).
    if (!quick) s.variants.push_back({"15 samples max radius 4", "shadows,motion_blur", {shutter, "motion_blur.samples=15", "motion_blur.max_radius=4"}});
    s.variants.push_back({"no motion blur", "shadows", {shutter}});
    s.shipped = "15 samples";
    // A scene given to the bench calls for it when it is animated (the bench poses animation 0).
    s.needed = [](const Features& f) { return f.view_amount("motion_blur") > 0.0 || (f.source && !f.source->animations.empty()); };
    return {s};
}

}  // namespace candela
