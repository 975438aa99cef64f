#pragma once
// Where reflection probes go (the env_probe pass). Declared probes are the nodes with
// `extras.reflection_probe`. Without any (or with probe.placement=auto) the probes are planned
// by what they contribute (plan_probes): every reflective object (a node drawing smooth metal or
// a transmissive material) is served by one probe with no box (an infinitely distant lookup that
// covers the bounding sphere of the objects it serves); objects whose probes would see nearly
// the same surroundings share one, and when there are more than probe.budget, the probes that
// matter least on screen are merged into others first. Every reflective object keeps a probe.
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "effects/reflections/reflections_data.h"
#include "render/gpu_scene.hpp"

namespace candela {

struct ReflectionsOptions;

struct ProbePlacement {
    std::string origin;      // "node 'NAME'" or "auto: 'NAME'" / "auto: 'A' + 3 more"
    glm::vec3 position{0.0f};
    bool has_box = false;    // box-projected lookups inside [box_min, box_max]
    glm::vec3 box_min{0.0f}, box_max{0.0f};
    float radius = 0.0f;     // influence without a box: points within radius of position
    // >= 0: lights only reflective surfaces (metallic rougher than this are not; transmissive
    // are): auto probes, whose sphere of influence also holds parts of other objects. < 0: all.
    float reflective_only = -1.0f;
    std::vector<int> excluded_draws;  // not captured: the draws of the nodes it serves, reflective draws around it
    std::vector<int> nodes;           // auto probes: the nodes (reflective objects) it serves
    float weight = 0.0f;              // auto probes: sum of its objects' ProbeObject::weight
};

// A material that calls for reflections: smooth metal, or transmission.
bool is_reflective(const Material& m, float max_roughness);

// A reflective object: a node that draws reflective materials (not blended), in world space.
struct ProbeObject {
    int node = -1;
    std::string name;
    Bounds bounds;             // of its reflective primitives
    float reflectance = 0.0f;  // (0, 1]: the largest transmission, or smooth-metal weight, of its primitives
    float coverage = 0.0f;     // fraction of the image its bounds cover (0 when unknown or off-screen)
    float weight = 0.0f;       // what a probe of its own is worth: (coverage + 1e-3) * reflectance
};

// The scene's reflective objects and the world bounds of every drawn primitive with its node
// (the surroundings a probe sees), from the scene alone (no GPU scene needed: `candela info`).
struct ProbeInputs {
    std::vector<ProbeObject> objects;
    std::vector<std::pair<int, Bounds>> geometry;  // (node, world bounds) per drawn primitive
};
ProbeInputs probe_inputs(const Scene& scene, float max_roughness);

// The image fraction a world box covers under view_proj (the bounding rectangle of its corners
// in front of the camera, clipped to the image); 0 if all behind.
float screen_coverage(const Bounds& b, const glm::mat4& view_proj);

struct ProbePlanOptions {
    int budget = 8;             // probe.budget: at most this many probes
    float merge_error = 0.25f;  // probe.merge: objects share a probe when its parallax error stays below
};

struct ProbePlan {
    std::vector<ProbeObject> objects;
    std::vector<ProbePlacement> probes;  // most important (weight) first
    std::vector<int> object_probe;       // per object: the probe that serves it
    int merged_freely = 0;               // merges under probe.merge
    int merged_for_budget = 0;           // merges forced by probe.budget
    std::string summary;                 // one line for the log and `candela info`
};

// Plans the automatic probes. Start: a probe per object at its bounds' centre. Merging two
// groups puts their probe at the centre of their joint bounds; its parallax error is how far
// the group's objects are from the probe relative to the probe's clearance (the distance to the
// nearest surface of other geometry: outside a box, the distance to it; inside, to its nearest
// face): error = max |object centre - probe| / clearance. Groups merge while the cheapest
// merge has error < merge_error; then, while there are more than `budget`, the merge of least
// error x weight (screen coverage x reflectance of both groups) is made. Probes are ranked by
// weight, heaviest first.
ProbePlan plan_probes(const ProbeInputs& inputs, const ProbePlanOptions& options);

std::vector<ProbePlacement> place_probes(const Scene& scene, const std::vector<GpuScene::Draw>& draws,
                                         const ReflectionsOptions& options, const glm::mat4* view_proj, std::string* summary);

// A probe as the lighting reads it (effects/reflections/reflections_data.h).
using ProbeData = gpu::ProbeData;
ProbeData to_gpu(const ProbePlacement& p);

}  // namespace candela
