#include "effects/transparency/transparency_sweep.hpp"

#include <string>

#include "render/features.hpp"

namespace candela {

std::vector<AccuracySweep> transparency_accuracy_sweeps(bool /*quick*/) {
    AccuracySweep s;
    s.effect = "transparency";
    s.scene = "transparency.gltf";
    s.own_passes = {"transparent", "transparent_peeling"};
    s.reference = AccuracySweep::Reference{rt::Mode::whitted, 1, 0, 0};
    s.compared = "final colour vs `--raytrace whitted --max-depth 0` (every blended layer along the camera ray, in order)";
    s.reading = "Sorting whole objects is wrong where they interpenetrate (alpha1 * alpha2 * |C1 - C2| in the "
                "overlap); depth peeling is exact up to its layer count. The floor common to all rows is the "
                "rest of the raster image (shadow filtering, area lights as pieces) against the tracer.";
    s.variants = {{"sorted by object", "shadows,transparency", {"transparency.sort=object"}},
                  {"sorted by triangle", "shadows,transparency", {"transparency.sort=triangle"}},
                  {"peeling 2", "shadows,transparency", {"transparency.mode=peeling", "transparency.layers=2"}},
                  {"peeling 4", "shadows,transparency", {"transparency.mode=peeling", "transparency.layers=4"}},
                  {"peeling 8", "shadows,transparency", {"transparency.mode=peeling", "transparency.layers=8"}}};
    s.shipped = "sorted by object";
    s.needed = [](const Features& f) { return f.decision("transparency").needed; };
    return {s};
}

}  // namespace candela
