#pragma once
// Indirect light from reflective shadow maps (engine/effects/rsm/; Dachsbacher & Stamminger
// 2005): one bounce of the lights with shadow views (punctual lights, and area lights through
// their shadowed pieces), gathered in screen space.
#include "render/effect.hpp"

namespace candela {

enum class RsmGather { full, half, quarter };
inline constexpr ChoiceName<RsmGather> kRsmGathers[] = {
    {"full", RsmGather::full}, {"half", RsmGather::half}, {"quarter", RsmGather::quarter}};

struct RsmOptions {
    int resolution = 256;                // [16, 4096] texels per side of each light's RSM view
    int samples = 64;                    // [1, 1024] RSM texels gathered per pixel and light
    RsmGather gather = RsmGather::half;  // resolution of the gather pass
    float radius = 0.15f;                // (0, 1] sampling radius, fraction of the RSM's width
    int max_lights = 4;                  // [1, 8] lights with an RSM: directional first, then brightest
                                         // (an area light, all its pieces, counts as one)
    int area_pieces = 4;                 // [1, 64] an area light's shadowed pieces with RSM views; the
                                         // flux of the others is carried by these
};

const Effect& rsm_effect();

}  // namespace candela
