#pragma once
// Where reflection probes go (the env_probe pass). Declared probes are the
// nodes with `extras.reflection_probe`; without any (or with probe.placement=auto), one probe at
// the centre of each reflective object's bounds, with no box: an infinitely distant lookup that
// covers the object's bounding sphere.
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "effects/reflections/reflections_data.h"
#include "render/gpu_scene.hpp"

namespace candela {

struct ReflectionsOptions;

struct ProbePlacement {
    std::string origin;      // "node 'NAME'" or "auto: 'NAME'"
    glm::vec3 position{0.0f};
    bool has_box = false;    // box-projected lookups inside [box_min, box_max]
    glm::vec3 box_min{0.0f}, box_max{0.0f};
    float radius = 0.0f;     // influence without a box: points within radius of position
    // >= 0: lights only reflective surfaces (metallic rougher than this are not; transmissive
    // are): auto probes, whose sphere of influence also holds parts of other objects. < 0: all.
    float reflective_only = -1.0f;
    std::vector<int> excluded_draws;  // draws whose bounds contain the position: not captured
};

// At most this many probes (the nearest-to-the-scene-centre first is not implied: declared
// order, then draw order); the rest are dropped with a warning from the renderer.
constexpr int kMaxProbes = 16;

// A material that calls for reflections: smooth metal, or transmission.
bool is_reflective(const Material& m, float max_roughness);

std::vector<ProbePlacement> place_probes(const Scene& scene, const std::vector<GpuScene::Draw>& draws,
                                         const ReflectionsOptions& options);

// A probe as the lighting reads it (effects/reflections/reflections_data.h).
using ProbeData = gpu::ProbeData;
ProbeData to_gpu(const ProbePlacement& p);

}  // namespace candela
