#pragma once
// The committed LTC table (ltc_table.inc, written by effects/area_lights/ltc_fit) as arrays for upload:
// kTableSize^2 entries, index j * kTableSize + i (layout and parametrisation: ltc.hpp).
#include <glm/glm.hpp>

#include <vector>

namespace candela::ltc {

std::vector<glm::vec4> table_matrices();    // M^-1 entries per ltc.hpp
std::vector<glm::vec2> table_amplitudes();  // (norm, fresnel)

}  // namespace candela::ltc
