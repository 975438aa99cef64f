#include "effects/reflections/reflections_sweep.hpp"

#include <string>

#include "render/features.hpp"

namespace candela {

std::vector<AccuracySweep> reflections_accuracy_sweeps(bool quick) {
    AccuracySweep s;
    s.effect = "reflections";
    s.scene = "reflections.gltf";
    s.own_passes = {"env_probe", "forward_opaque"};
    s.reference = AccuracySweep::Reference{rt::Mode::whitted, 1, 1, 0};
    s.compared = "final colour vs `--raytrace whitted --max-depth 1`; probes re-captured every frame (probe.update=every_frame) so their cost is measured";
    s.reading = "Without probes a mirror shows the constant environment; a probe at the object's centre "
                "(infinite-distance lookup) gets directions right but parallax wrong; a box-projected probe "
                "is nearly exact on the walls of a box room. What remains is what the probe cannot see "
                "(the tracer's depth limit, objects inside the room) and the probe's resolution, which stops "
                "mattering once a probe texel is smaller than the mirror's pixels. Every row also carries the "
                "rest of the raster image's error (SSAO is off, shadows filtered), a floor near 0.07 here.";
    s.variants.push_back({"static environment", "shadows", {}});
    s.variants.push_back({"dynamic probe 128", "shadows,reflections", {"probe.placement=auto", "probe.update=every_frame"}});
    for (int r : quick ? std::vector<int>{64, 128} : std::vector<int>{32, 64, 128, 256})
        s.variants.push_back({"box probe " + std::to_string(r), "shadows,reflections",
                              {"probe.resolution=" + std::to_string(r), "probe.update=every_frame"}});
    s.shipped = "box probe 128";
    s.needed = [](const Features& f) { return f.decision("reflections").needed; };
    return {s};
}

}  // namespace candela
