#include "rt/ray_rates.hpp"

#include <algorithm>
#include <memory>
#include <vector>

#include "render/still.hpp"
#include "rt/ray_tracer.hpp"

namespace candela::rt {

RayRates measure_ray_rates(const ShaderLibrary& shaders, const Scene& scene, GpuScene& gpu, const Camera& camera,
                           int width, int height, int spp, int repeats) {
    const Mode modes[3] = {Mode::primary, Mode::ao, Mode::bounce};
    std::vector<std::unique_ptr<RayTracer>> tracers;
    for (const Mode m : modes) {
        Options o;
        o.mode = m;
        o.ao_radius = 1e30f;  // AO rays as long as shadow rays to a directional light
        o.spp = 1;
        tracers.push_back(std::make_unique<RayTracer>(shaders, scene, gpu, o));
        tracers.back()->render(camera, width, height);  // warm-up
        tracers.back()->set_spp(spp);
    }
    std::vector<double> primary_ms, ao_extra_ms, bounce_extra_ms;
    for (int r = 0; r < std::max(repeats, 1); ++r) {
        double ms[3];
        for (int m = 0; m < 3; ++m) ms[m] = tracers[static_cast<std::size_t>(m)]->render(camera, width, height).trace_ms;
        primary_ms.push_back(ms[0]);
        ao_extra_ms.push_back(ms[1] - ms[0]);
        bounce_extra_ms.push_back(ms[2] - ms[0]);
    }
    RayRates out;
    out.bvh = tracers[0]->scene().geometry().bvh.stats;
    out.triangles = tracers[0]->scene().geometry().triangles.size();
    const TraversalLayout layout = pack_traversal(tracers[0]->scene().geometry());
    out.node_bytes = layout.nodes.size() * sizeof(layout.nodes[0]);
    out.prim_bytes = layout.prims.size() * sizeof(layout.prims[0]);
    const double rays = static_cast<double>(width) * height * spp;
    auto rate = [&](double ms) { return ms > 0.0 ? rays / (ms * 1e3) : 0.0; };
    out.primary_mrays = rate(median(primary_ms));
    out.ao_mrays = rate(median(ao_extra_ms));
    out.bounce_mrays = rate(median(bounce_extra_ms));
    Options counting;
    counting.mode = Mode::primary;
    counting.spp = std::min(spp, 16);  // one dispatch's samples, as timed (32-bit counters)
    counting.traversal_stats = true;
    const Result counted = RayTracer(shaders, scene, gpu, counting).render(camera, width, height);
    out.nodes_per_ray = counted.nodes_per_ray;
    out.primitives_per_ray = counted.primitives_per_ray;
    out.lane_utilisation = counted.lane_utilisation;
    counting.mode = Mode::ao;
    counting.ao_radius = 1e30f;
    const Result both = RayTracer(shaders, scene, gpu, counting).render(camera, width, height);
    if (both.traversal_rays > counted.traversal_rays) {
        const double rays = static_cast<double>(both.traversal_rays - counted.traversal_rays);
        const double steps = static_cast<double>(both.traversal_steps) - static_cast<double>(counted.traversal_steps);
        out.ao_nodes_per_ray = steps / rays;
        out.ao_primitives_per_ray =
            (static_cast<double>(both.traversal_primitives) - static_cast<double>(counted.traversal_primitives)) / rays;
        const double slots = static_cast<double>(both.traversal_slots) - static_cast<double>(counted.traversal_slots);
        if (slots > 0.0) out.ao_lane_utilisation = steps / slots;
    }
    return out;
}

}  // namespace candela::rt
