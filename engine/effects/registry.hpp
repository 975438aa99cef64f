#pragma once
// The effect registry: every effect module, in the order their decisions are made and their
// passes are added within a stage (an effect may depend on the decisions before it).
#include <string_view>
#include <vector>

#include "effects/effect.hpp"

namespace candela {

const std::vector<const Effect*>& effect_registry();
// nullptr for an unknown name.
const Effect* find_effect(std::string_view name);

}  // namespace candela
