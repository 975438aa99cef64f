#pragma once
// `candela bench accuracy`: what accuracy costs in time. For every effect, a sweep of its knobs;
// each setting's time (median GPU ms of the effect's own passes, with the interquartile range)
// and its error against the ray tracer's reference of the same quantity (whose own noise is
// measured from two seeds). Writes results.csv, report.md, one SVG plot per effect and image
// strips (raster | reference | difference).
#include <filesystem>
#include <string>
#include <vector>

#include "platform/context.hpp"

namespace candela::cli {

struct AccuracyOptions {
    std::vector<std::string> scenes;  // empty: each effect's own sample scene
    std::filesystem::path out;
    std::filesystem::path report;     // the Markdown report (default OUT/report.md); links are relative to it
    std::filesystem::path shader_dir;
    std::filesystem::path scene_dir;  // where the sample scenes are
    Backend backend = Backend::auto_select;
    bool quick = false;               // reduced sweeps on small images (CI)
    std::vector<std::string> effects; // --effect NAME (repeatable): only these sections; empty: all
    std::string command_line;         // recorded in the report
};

int run_accuracy(const AccuracyOptions& options);

}  // namespace candela::cli
