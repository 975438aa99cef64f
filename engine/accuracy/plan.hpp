#pragma once
// Planning an accuracy run (internal to engine/accuracy): the sweeps (every registered effect's,
// then the three that belong to no effect) and the sections, a sweep on one scene each, in
// report order. No GL context.
#include <cstddef>
#include <string>
#include <vector>

#include "accuracy/accuracy.hpp"
#include "effects/accuracy_sweep.hpp"
#include "scene/scene.hpp"

namespace candela::accuracy {

// The image size and frame counts of a run, and the steps of the three sweeps that belong to no
// effect.
struct Sizes {
    int width, height, warmup, frames;
};
Sizes sizes(bool quick);
std::vector<int> light_counts(bool quick);
std::vector<int> spp_steps(bool quick);
std::vector<int> depth_steps(bool quick);

// One section of the report: a sweep on one scene.
struct Job {
    std::size_t sweep = 0;  // index in Plan::sweeps
    std::string scene;      // the sweep's own scene, or a given one that calls for the effect
};

struct Plan {
    std::vector<AccuracySweep> sweeps;
    std::vector<Job> jobs;
    const AccuracySweep& sweep(const Job& j) const { return sweeps[j.sweep]; }
};

// The sections in report order. Given scenes are loaded and analysed on the CPU (no GL context):
// a sweep runs on those that call for its effect.
Plan make_plan(const Options& o);

// The scene a section's heading names (forward_deferred runs on generated scenes of N lights).
std::string section_scene(const AccuracySweep& s, const std::string& scene);
std::string job_label(const Plan& plan, const Job& j);

// The progress steps of a section (references and rows).
int job_steps(const AccuracySweep& s, bool quick);

// A scene by the name a sweep or the user gives it: generated:... or a glTF file (a bare file
// name is one of the sample scenes, in o.scene_dir).
Scene load_scene(const Options& o, const std::string& name);

}  // namespace candela::accuracy
