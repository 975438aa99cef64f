#pragma once
// The dof accuracy sweep for `candela bench accuracy` (effects/accuracy_sweep.hpp).
#include <vector>

#include "effects/accuracy_sweep.hpp"

namespace candela {

std::vector<AccuracySweep> dof_accuracy_sweeps(bool quick);

}  // namespace candela
