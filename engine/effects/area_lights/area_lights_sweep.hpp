#pragma once
// The area lights accuracy sweep for `candela bench accuracy` (effects/accuracy_sweep.hpp).
#include <vector>

#include "effects/accuracy_sweep.hpp"

namespace candela {

std::vector<AccuracySweep> area_lights_accuracy_sweeps(bool quick);

}  // namespace candela
