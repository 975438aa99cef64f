#pragma once
// The rasterizer's area-light approximation (engine/effects/area_lights/): each emissive
// primitive becomes arealight.samples Lambertian pieces (render/gpu_scene.hpp: AreaPiece), each
// a light at its piece's centroid with its own shadow map and a PCSS penumbra of the piece's
// size. It has no pass of its own: the pieces join the light buffer, which every lighting pass
// reads. It is not switchable: emitters are lights whenever the scene has them.
#include "effects/effect.hpp"

namespace candela {

struct AreaLightsOptions {
    int samples = 4;  // [1, 64] shadowed Lambertian pieces per emissive primitive
};

const Effect& area_lights_effect();

}  // namespace candela
