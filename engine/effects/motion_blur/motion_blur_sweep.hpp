#pragma once
// The motion_blur accuracy sweep for `candela bench accuracy` (effects/accuracy_sweep.hpp).
#include <vector>

#include "effects/accuracy_sweep.hpp"

namespace candela {

std::vector<AccuracySweep> motion_blur_accuracy_sweeps(bool quick);

}  // namespace candela
