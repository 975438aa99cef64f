#pragma once
// Depth of field (engine/effects/dof/): the raster approximation of the thin-lens camera
// (Camera::aperture, Camera::focus_distance; the tracer samples the lens exactly). After
// everything is drawn (Stage::post, after the anti-aliasing resolve), a gather blurs the HDR image
// by each pixel's circle of confusion, sized by the same thin-lens formula as the tracer's, with
// separate near and far fields composited in one pass (docs/effects/dof.md). Planned only when the
// camera has an aperture.
#include "render/effect.hpp"

namespace candela {

struct DofOptions {
    // [2, 256] largest circle of confusion, DIAMETER in pixels; larger blur circles are clamped
    // to it (the gather's footprint, and so the spacing of its samples, grows with it).
    float max_coc = 48.0f;
    int samples = 32;  // [4, 256] gather samples per field (near, far) per pixel
};

const Effect& dof_effect();

}  // namespace candela
