#pragma once
// `candela bench accuracy`: what accuracy costs in time. For every effect, a sweep of its knobs;
// each setting's time (median GPU ms of the effect's own passes, with the interquartile range)
// and its error against the ray tracer's reference of the same quantity (whose own noise is
// measured from two seeds). Writes results.csv, report.md, one SVG plot per effect and image
// strips (raster | reference | difference).
//
// The run is made of sections (a sweep on one scene), which can also run one per process (a
// cluster array task each: run_accuracy_section) and be assembled afterwards (assemble_accuracy)
// into the same outputs: both paths write them with the same code, from the same numbers.
#include <filesystem>
#include <string>
#include <vector>

#include "commands.hpp"
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

// One section of the run.
struct AccuracyTask {
    std::string effect;  // the sweep ("ssao", "ray_tracer", ...)
    std::string scene;   // its scene as the report names it ("cornell_box.gltf", "generated:lights:N")
    std::string label;   // "ssao on cornell_box.gltf"
};

// The whole run in one process (a GL context): every section, then the outputs.
int run_accuracy(const AccuracyOptions& options);

// bench accuracy's options from its parsed arguments (scenes, -o, --report, --shader-dir,
// --backend, --effect, --quick, --quiet; cmd_bench.cpp); `command` and `args` make the command
// line the report records. Also what `candela farm sweep` tasks run with.
struct Parsed;
AccuracyOptions accuracy_options(const Parsed& p, const Args& args, const std::string& command);

// The sections of a run with these options, in report order; index i is run_accuracy_section's
// `index`. No GL context (given scenes are loaded and analysed on the CPU). Throws bad_input for
// an --effect that names no section, or a scene that does not load.
std::vector<AccuracyTask> plan_accuracy(const AccuracyOptions& options);

// Runs section `index` alone (its own GL context) and saves its result in section_dir
// (section.json, reference.exr, row_NNN.exr; section.json written last, so a directory that has
// one is complete). Already complete for the same effect, scene and --quick: prints that it
// skipped and returns 0. The saved result is read back and checked bit for bit. Returns 0, or 3
// without a GL context; throws bad_input (2) for an index out of range.
int run_accuracy_section(const AccuracyOptions& options, int index, const std::filesystem::path& section_dir);

// Writes results.csv, the report, plots and strips (to options.out / options.report) from saved
// sections: section_dirs[i] holds section i (all of them, in plan_accuracy order; options as
// for the sections: same scenes, --effect and --quick). The report's device line comes from the
// sections. No GL context. A missing or incomplete section: a message naming its directory and
// label for each, nothing written, Error internal (exit 1); a wrong number of directories:
// bad_input (2).
int assemble_accuracy(const AccuracyOptions& options, const std::vector<std::filesystem::path>& section_dirs);

}  // namespace candela::cli
