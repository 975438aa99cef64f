#pragma once
// Every GLSL program Candela builds, by name, so that the renderer, the hot reloader and
// `candela shaders check` agree on what exists.
#include <string>
#include <vector>

#include "shader/shader_library.hpp"

namespace candela {

// The raster renderer's programs: the base ones (forward, sky, tonemap, gbuffer,
// deferred_light, depth_normals, copy; image-based lighting: brdf_lut, equirect_to_cube,
// prefilter; the viewer's buffer inspector: debug_view), then every registered effect's
// (Effect::programs()). program_desc throws candela::Error (internal) for an unknown name.
const ProgramDesc& program_desc(const std::string& name);
const std::vector<ProgramDesc>& raster_programs();

// The ray tracer's variants worth checking: every mode with no scene feature and with all of
// them (the feature blocks are additive #ifdefs, so the two ends cover every line).
std::vector<ProgramDesc> ray_tracer_variants();

}  // namespace candela
