#pragma once
// Distance fog (engine/effects/fog/): a demo of a complete effect module.
#include "effects/effect.hpp"

namespace candela {
const Effect& fog_effect();
}
