#include "rt/tracer_options.hpp"

namespace candela::rt {

Options tracer_options(const RenderSettings& s) {
    Options o;
    o.ao_radius = s.ao.radius;
    o.whitted_max_roughness = s.rt.whitted_max_roughness;
    o.indirect_occlusion = s.rt.indirect_occlusion;
    o.env_importance = s.rt.env_importance;
    o.visibility_light = s.debug.light;
    o.jitter = s.rt.jitter == RtJitter::automatic ? -1 : s.rt.jitter == RtJitter::on ? 1 : 0;
    o.shutter_slices = s.rt.shutter_slices;
    return o;
}

bool tracer_reads_knob(const std::string& name) {
    for (const char* prefix : {"rt.", "camera."})
        if (name.rfind(prefix, 0) == 0) return true;
    return name == "ao.radius" || name == "debug.light";
}

}  // namespace candela::rt
