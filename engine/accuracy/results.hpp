#pragma once
// The accuracy engine's measurements (internal to engine/accuracy): a row per knob setting, a
// section per sweep on one scene. A run in one process and an assembly of saved sections hold
// the same numbers in these, and every output is written from them (report.hpp).
#include <cstddef>
#include <limits>
#include <string>

#include "effects/accuracy_sweep.hpp"
#include "image/image.hpp"

namespace candela::accuracy {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
using Buffer = AccuracySweep::Buffer;  // what a raster variant outputs, and how it is compared

// One setting of a sweep: its time and its error (NaN: not measured).
struct Row {
    std::string effect, variant, settings, scene;
    int width = 0, height = 0;
    double ms = kNaN, iqr = kNaN, frame_ms = kNaN;
    double rmse = kNaN, relmse = kNaN, max_abs = kNaN, pct_over = kNaN, flip = kNaN;
    double rmse_no_occlusion = kNaN;
    int ref_spp = 0;
    double ref_noise = kNaN;
    bool pareto = false, at_noise_floor = false;
    ImageF image;  // raster output (kept for the strips)
};

// A section's result: its rows are rows[first, last) of the run's row list.
struct Section {
    const AccuracySweep* sweep = nullptr;
    std::string scene;
    std::size_t first = 0, last = 0;
    double noise = 0, rt_ms = 0;
    int ref_spp = 0;
    double occlusion_rmse = kNaN;  // a split sweep: RMSE of the reference with vs without occlusion
    ImageF reference;
    std::string knee_name;         // the knee of the Pareto front (empty: none), for the saved section
    std::string device, backend;   // where it ran
    double seconds = 0;            // how long it took
};

struct Device {
    std::string device, backend;
    bool operator==(const Device&) const = default;
};

// A number as the CSV, the report and the plots print it (printf format `f`); "" for NaN or
// infinity (report.cpp).
std::string num(double v, const char* f = "%.4g");

}  // namespace candela::accuracy
