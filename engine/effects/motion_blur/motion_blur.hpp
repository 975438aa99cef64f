#pragma once
// Raster motion blur (engine/effects/motion_blur/): the approximation of the tracer's
// exact motion blur (camera.shutter; the tracer poses the scene at random times in the shutter).
// After everything is drawn (Stage::post, after the anti-aliasing resolve and before depth of
// field), a velocity pass redraws the scene's geometry with its positions at shutter open and
// close (GpuScene::set_motion) and a reconstruction filter after McGuire, Hennessy, Bukowski and
// Osman 2012, "A Reconstruction Filter for Plausible Motion Blur" (TileMax, NeighborMax and a
// gather along the dominant velocity with soft depth comparisons and cone/cylinder weights)
// blurs the HDR image (docs/effects/motion_blur.md). Planned only when the shutter is open and something
// in view moves during it (its view amount: the moving draws in view).
#include "render/effect.hpp"

namespace candela {

struct MotionBlurOptions {
    // [1, 64] the largest blur, in pixels from a pixel to either end of its motion (half the
    // motion over the shutter); longer motions are clamped to it. Also the side of the TileMax
    // tiles (the paper's k): the gather reaches at most one tile beyond a pixel's own.
    int max_radius = 20;
    int samples = 15;       // [3, 255] taps of the gather along the dominant velocity (odd: the centre tap is the pixel itself)
    float soft_z = 0.05f;   // [1e-4, 10] the soft depth comparison's extent, as a fraction of the pixel's view depth
};

const Effect& motion_blur_effect();

}  // namespace candela
