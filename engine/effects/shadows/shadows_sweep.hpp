#pragma once
// The shadow accuracy sweeps for `candela bench accuracy` (effects/accuracy_sweep.hpp): the
// visibility of one light ("shadows") and the final colour ("shadows_colour").
#include <vector>

#include "effects/accuracy_sweep.hpp"

namespace candela {

std::vector<AccuracySweep> shadows_accuracy_sweeps(bool quick);

}  // namespace candela
