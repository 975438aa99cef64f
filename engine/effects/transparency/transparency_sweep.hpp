#pragma once
// The transparency accuracy sweep for `candela bench accuracy` (effects/accuracy_sweep.hpp).
#include <vector>

#include "effects/accuracy_sweep.hpp"

namespace candela {

std::vector<AccuracySweep> transparency_accuracy_sweeps(bool quick);

}  // namespace candela
