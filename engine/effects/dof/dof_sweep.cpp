#include "effects/dof/dof_sweep.hpp"

#include <string>

#include "render/features.hpp"

namespace candela {

std::vector<AccuracySweep> dof_accuracy_sweeps(bool quick) {
    AccuracySweep s;
    s.effect = "dof";
    s.scene = "generated:dof";
    s.buffer = AccuracySweep::Buffer::radiance;
    // Time: the whole frame (no own passes named), so that the pinhole row, which runs none of the
    // effect's passes, has one too; the effect's cost is the difference to that row.
    s.own_passes = {};
    // The box-filtered pixel with the lens sampled: jitter on, every sample a new lens point.
    AccuracySweep::Reference ref{rt::Mode::direct, quick ? 64 : 256};
    ref.jitter = 1;
    s.reference = ref;
    s.compared = "radiance vs `--raytrace direct` with the camera's thin lens sampled per ray and the pixel box-filtered "
                 "(jitter on); the last row is the raster pinhole image (`--set camera.aperture=0`) against the same reference. "
                 "Times are whole frames: the effect's cost is a row's time minus the pinhole row's";
    s.reading = "The gather sees one layer: what the near object hides is unknown, so the background behind its blurred "
                "edge is guessed from the far pixels around it, and a blurred far surface cannot be seen past a sharper one. "
                "Fewer samples add noise (the spiral turns per pixel); the rest is the raster image's own error (edges "
                "without anti-aliasing, shadow maps), the same in the pinhole row.";
    // The reference uses the first variant's lens (the scene camera's): the pinhole row goes last.
    const std::vector<int> samples = quick ? std::vector<int>{8, 32} : std::vector<int>{8, 16, 32, 64};
    for (int n : samples) s.variants.push_back({std::to_string(n) + " samples", "shadows,dof", {"dof.samples=" + std::to_string(n)}});
    // A clamp below the near object's blur circles (about 10 pixels across at 240 high): its cost in error.
    if (!quick) s.variants.push_back({"32 samples max CoC 6", "shadows,dof", {"dof.samples=32", "dof.max_coc=6"}});
    s.variants.push_back({"pinhole (no DOF)", "shadows,dof", {"camera.aperture=0"}});
    s.shipped = "32 samples";
    s.needed = [](const Features& f) { return f.view_amount("dof") > 0.0; };
    return {s};
}

}  // namespace candela
