#pragma once
#include <vector>

#include "effects/accuracy_sweep.hpp"

namespace candela {

// The accuracy-vs-time sweep of the GI probes against `--raytrace path` (engine/effects/gi/).
std::vector<AccuracySweep> gi_accuracy_sweeps(bool quick);

}  // namespace candela
