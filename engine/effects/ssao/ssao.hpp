#pragma once
// Screen-space ambient occlusion (engine/effects/ssao/): the AO buffer from the camera's depth and
// normals, at full or half resolution, and a separable depth-aware blur; the lighting multiplies
// only the ambient/environment term by it (ssao_shading.glsl). It converges to `--raytrace ao`.
#include "render/effect.hpp"

namespace candela {

enum class SsaoResolution { full, half };
inline constexpr ChoiceName<SsaoResolution> kSsaoResolutions[] = {{"full", SsaoResolution::full}, {"half", SsaoResolution::half}};

struct SsaoOptions {
    int samples = 16;  // [1, 256] directions per pixel
    int steps = 4;     // [1, 32] steps marched along each direction
    // half: a quarter of the cost for +0.002 RMSE (the SSAO accuracy sweep)
    SsaoResolution resolution = SsaoResolution::half;
    int blur = 4;         // [0, 16] bilateral blur radius in AO pixels (0: no blur passes)
    float bias = 0.02f;   // [0, 0.5] start offset and depth tolerance, fraction of ao.radius
};

const Effect& ssao_effect();

}  // namespace candela
