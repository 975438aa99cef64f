#pragma once
// The tracer's options that knobs set, in one place: render --raytrace, the viewer's reference,
// bench accuracy and the farm all start from tracer_options(settings), then set what is theirs
// (mode, samples, seed, shards, motion), so a knob cannot reach one of them and miss another.
#include <string>

#include "render/settings.hpp"
#include "rt/ray_tracer.hpp"

namespace candela::rt {

// rt.* (jitter, whitted_max_roughness, indirect_occlusion, env_importance, shutter_slices),
// ao.radius and debug.light (visibility mode's light) into a default Options.
Options tracer_options(const RenderSettings& settings);

// Whether a knob can change a traced image: the ones tracer_options reads, and camera.* (the lens
// and shutter the tracer applies to its camera). Every other knob is the rasterizer's.
bool tracer_reads_knob(const std::string& name);

}  // namespace candela::rt
