#include "effects/area_lights/ltc_table.hpp"

#include "core/error.hpp"
#include "effects/area_lights/ltc.hpp"

namespace candela::ltc {
namespace {
// The table is data made by effects/area_lights/ltc_fit, which itself links this library: before the first
// fit (bootstrap only; the table is committed) the engine builds without it and says so when
// the table is needed.
#if __has_include("effects/area_lights/ltc_table.inc")
#include "effects/area_lights/ltc_table.inc"
constexpr bool kHaveTable = true;
#else
constexpr bool kHaveTable = false;
constexpr float kLtcMatrix[1][4] = {{1, 0, 1, 0}};
constexpr float kLtcAmplitude[1][2] = {{0, 0}};
#endif

void require_table() {
    if (!kHaveTable) throw Error(ExitCode::internal, "engine/effects/area_lights/ltc_table.inc is missing: build and run ltc_fit");
}
}  // namespace

std::vector<glm::vec4> table_matrices() {
    require_table();
    std::vector<glm::vec4> out(static_cast<size_t>(kTableSize * kTableSize));
    for (size_t i = 0; i < out.size(); ++i) out[i] = glm::vec4(kLtcMatrix[i][0], kLtcMatrix[i][1], kLtcMatrix[i][2], kLtcMatrix[i][3]);
    return out;
}

std::vector<glm::vec2> table_amplitudes() {
    require_table();
    std::vector<glm::vec2> out(static_cast<size_t>(kTableSize * kTableSize));
    for (size_t i = 0; i < out.size(); ++i) out[i] = glm::vec2(kLtcAmplitude[i][0], kLtcAmplitude[i][1]);
    return out;
}

}  // namespace candela::ltc
