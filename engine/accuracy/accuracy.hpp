#pragma once
// The accuracy engine: what accuracy costs in time (`candela bench accuracy`, `candela farm
// sweep`). For every effect, a sweep of its knobs; each setting's time (median GPU ms of the
// effect's own passes, with the interquartile range) and its error against the ray tracer's
// reference of the same quantity (whose own noise is measured from two seeds). Writes
// results.csv, report.md, one SVG plot per effect and image strips (raster | reference |
// difference).
//
// The run is made of sections (a sweep on one scene), which can also run one per process (a
// cluster array task each: run_section) and be assembled afterwards (assemble) into the same
// outputs: both paths write them with the same code, from the same numbers.
//
// This header is all a caller needs. The engine prints nothing: what the user should read comes
// back as results, or through an Observer while the work goes on; the CLI decides how to print
// it. The parts, by concern: plan.hpp (the sections), run.hpp (references and knob settings on
// GL), metrics.hpp (errors, the Pareto front), plots.hpp (SVG, image strips), report.hpp (CSV
// and report.md), section_file.hpp (a section saved to and read from a directory).
#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "platform/context.hpp"

namespace candela::accuracy {

struct Options {
    std::vector<std::string> scenes;  // empty: each effect's own sample scene
    std::filesystem::path out;
    std::filesystem::path report;     // the Markdown report (default OUT/report.md); links are relative to it
    std::filesystem::path shader_dir;
    std::filesystem::path scene_dir;  // where the sample scenes are
    Backend backend = Backend::auto_select;
    bool quick = false;               // reduced sweeps on small images (CI)
    std::vector<std::string> effects; // only the sections of these sweeps ("ssao", ...); empty: all
    std::string command_line;         // recorded in the report
};

// One section of the run.
struct Task {
    std::string effect;  // the sweep ("ssao", "ray_tracer", ...)
    std::string scene;   // its scene as the report names it ("cornell_box.gltf", "generated:lights:N")
    std::string label;   // "ssao on cornell_box.gltf"
};

// What the engine tells its caller while it works. The default tells nobody.
class Observer {
public:
    virtual ~Observer() = default;
    // One step of `total` (a reference traced, a row measured) is done: `done` so far, `seconds`
    // since the work began.
    virtual void step(int /*done*/, int /*total*/, const std::string& /*what*/, double /*seconds*/) {}
    // A line for the user: why there is no GL context ("warning: ..." for a context's notice), a
    // stale section run again ("note: ..."), a missing section before assemble throws.
    virtual void message(const std::string& /*text*/) {}
};

// The outputs written by run and assemble.
struct Written {
    std::string devices;                  // the devices the sections ran on, "; " between them
    std::filesystem::path csv, report;    // results.csv and the Markdown report
    std::size_t sections = 0, rows = 0;
    double seconds = 0;                   // the whole run's (run) or the assembly's (assemble)
};

// What run_section did.
struct SectionDone {
    std::string label;     // the task's
    bool skipped = false;  // the directory already held it: nothing ran
    std::string device;    // where it ran
    std::size_t rows = 0;
    double seconds = 0;    // how long the section took
};

// The sections of a run with these options, in report order; index i is run_section's `index`.
// No GL context (given scenes are loaded and analysed on the CPU). Throws bad_input for an
// Options::effects entry that names no section, or a scene that does not load.
std::vector<Task> plan(const Options& options);

// The whole run in one process (a GL context): every section, then the outputs.
// std::nullopt: no GL context (the observer was told why).
std::optional<Written> run(const Options& options, Observer& observer);

// Runs section `index` alone (its own GL context) and saves its result in section_dir
// (section.json, reference.exr, row_NNN.exr; section.json written last, so a directory that has
// one is complete). Already complete for the same effect, scene and quick: returns `skipped`.
// The saved result is read back and checked bit for bit (Error internal if it differs).
// std::nullopt: no GL context (the observer was told why); throws bad_input for an index out of
// range.
std::optional<SectionDone> run_section(const Options& options, int index, const std::filesystem::path& section_dir,
                                       Observer& observer);

// Writes results.csv, the report, plots and strips (to options.out / options.report) from saved
// sections: section_dirs[i] holds section i (all of them, in plan order; options as for the
// sections: same scenes, effects and quick). The report's device line comes from the sections.
// No GL context. A missing or incomplete section: a message to the observer naming its
// directory and label for each, nothing written, Error internal; a wrong number of directories:
// bad_input.
Written assemble(const Options& options, const std::vector<std::filesystem::path>& section_dirs, Observer& observer);

}  // namespace candela::accuracy
