#pragma once
// Alpha-blended surfaces (engine/effects/transparency/): sorted blending back to front by object
// or by triangle, or exact depth peeling, drawn after the opaque image and the sky.
#include "render/effect.hpp"

namespace candela {

enum class TransparencySort { object, triangle };
inline constexpr ChoiceName<TransparencySort> kTransparencySorts[] = {{"object", TransparencySort::object},
                                                                      {"triangle", TransparencySort::triangle}};
enum class TransparencyMode { sorted, peeling };
inline constexpr ChoiceName<TransparencyMode> kTransparencyModes[] = {{"sorted", TransparencyMode::sorted},
                                                                      {"peeling", TransparencyMode::peeling}};

struct TransparencyOptions {
    // object: draws back to front by their bounds' centres; triangle also sorts each mesh's
    // triangles by their centroids, on the CPU every frame
    TransparencySort sort = TransparencySort::object;
    TransparencyMode mode = TransparencyMode::sorted;  // sorted blending, or exact depth peeling
    int layers = 8;                                    // [1, 64] depth-peeling layers
};

const Effect& transparency_effect();

}  // namespace candela
