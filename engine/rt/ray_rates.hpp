#pragma once
// Ray rates of the compute-shader tracer, as `candela bench rays` and bench_rays_embree report
// them (the latter next to Embree's, in the same run).
#include <cstddef>

#include "render/gpu_scene.hpp"
#include "rt/bvh.hpp"
#include "scene/scene.hpp"
#include "shader/shader_library.hpp"

namespace candela::rt {

struct RayRates {
    std::size_t triangles = 0;
    BvhStats bvh;
    // Millions of rays per second, medians over the repeats. An AO (bounce) sample is one camera
    // ray plus one any-hit (closest-hit, cosine-distributed) ray: the extra time prices the
    // second ray. 0 where the extra time was not positive.
    double primary_mrays = 0.0, ao_mrays = 0.0, bounce_mrays = 0.0;
    // Traversal work per camera ray (loop iterations: interior nodes and leaves), counted in a
    // separate run with RT_STATS.
    double nodes_per_ray = 0.0, primitives_per_ray = 0.0;
    double lane_utilisation = 0.0;  // of the camera rays' traversal steps (Result::lane_utilisation)
    // The same for the AO rays alone: an AO run's counts less the camera rays' (the same rays).
    double ao_nodes_per_ray = 0.0, ao_primitives_per_ray = 0.0, ao_lane_utilisation = 0.0;
    // Bytes of the traversal layout (rt::pack_traversal): node texels and primitive records.
    std::size_t node_bytes = 0, prim_bytes = 0;
};

// Renders `spp` samples per pixel at w x h in the primary, AO (unbounded rays, as shadow rays to a
// directional light) and bounce modes, after one warm-up sample each (llvmpipe compiles at the
// first dispatch). The three modes are timed in turn, `repeats` rounds.
RayRates measure_ray_rates(const ShaderLibrary& shaders, const Scene& scene, GpuScene& gpu, const Camera& camera,
                           int width, int height, int spp, int repeats);

}  // namespace candela::rt
