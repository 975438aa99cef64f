#include "effects/accuracy_sweep.hpp"

#include <utility>

#include "effects/registry.hpp"

namespace candela {

// The report's sections: every registered effect's sweeps, in registry order.
std::vector<AccuracySweep> effect_accuracy_sweeps(bool quick) {
    std::vector<AccuracySweep> all;
    for (const Effect* e : effect_registry())
        for (AccuracySweep& s : e->accuracy_sweeps(quick)) all.push_back(std::move(s));
    return all;
}

}  // namespace candela
