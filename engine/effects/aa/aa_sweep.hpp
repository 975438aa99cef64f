#pragma once
#include <vector>

#include "effects/accuracy_sweep.hpp"

namespace candela {

std::vector<AccuracySweep> aa_accuracy_sweeps(bool quick);

}  // namespace candela
