#pragma once
// Running an accuracy section on GL (internal to engine/accuracy): the ray tracer's references
// (two seeds), the raster variants' times and images, their errors and the Pareto front.
#include <chrono>
#include <optional>
#include <string>
#include <vector>

#include "accuracy/accuracy.hpp"
#include "accuracy/results.hpp"
#include "effects/accuracy_sweep.hpp"
#include "platform/context.hpp"
#include "shader/shader_library.hpp"

namespace candela::accuracy {

using Clock = std::chrono::steady_clock;

// The steps of a run (references and rows), told to the observer as each is done.
struct Progress {
    Observer& observer;
    int done = 0, total = 0;
    Clock::time_point start = Clock::now();
    void step(const std::string& what);
};

// What every section of a run shares: the options, the shaders, the image size and frame counts.
struct Run {
    const Options& o;
    const ShaderLibrary& shaders;
    int width, height, warmup, frames;
    Progress& progress;
};

// Runs one section (a GL context is current), appending its rows to `rows`.
Section run_job(const Run& c, const AccuracySweep& s, const std::string& job_scene, std::vector<Row>& rows);

// The GL context of a run (or of one section), and its device; std::nullopt when there is none
// (the observer is told why; a context's notice is told as a warning).
struct Gl {
    ContextResult ctx;
    Device device;
};
std::optional<Gl> open_gl(const Options& o, Observer& observer);

}  // namespace candela::accuracy
