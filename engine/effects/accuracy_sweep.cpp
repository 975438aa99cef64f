#include "effects/accuracy_sweep.hpp"

#include "effects/area_lights/area_lights_sweep.hpp"
#include "effects/reflections/reflections_sweep.hpp"
#include "effects/rsm/rsm_sweep.hpp"
#include "effects/shadows/shadows_sweep.hpp"
#include "effects/ssao/ssao_sweep.hpp"
#include "effects/transparency/transparency_sweep.hpp"

#include <utility>

namespace candela {

// The report's section order. To become a loop over the effect registry (each effect returns its
// folder's sweeps); until then a plain list.
std::vector<AccuracySweep> effect_accuracy_sweeps(bool quick) {
    std::vector<AccuracySweep> all;
    for (auto* sweeps : {shadows_accuracy_sweeps, area_lights_accuracy_sweeps, ssao_accuracy_sweeps, rsm_accuracy_sweeps,
                         transparency_accuracy_sweeps, reflections_accuracy_sweeps})
        for (AccuracySweep& s : sweeps(quick)) all.push_back(std::move(s));
    return all;
}

}  // namespace candela
