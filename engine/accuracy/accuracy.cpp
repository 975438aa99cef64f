// The accuracy engine's entry points (accuracy.hpp): the three ways through a plan - all
// sections in one process, one section into its directory, the outputs from saved sections.
#include "accuracy/accuracy.hpp"

#include <algorithm>
#include <exception>

#include "accuracy/plan.hpp"
#include "accuracy/report.hpp"
#include "accuracy/results.hpp"
#include "accuracy/run.hpp"
#include "accuracy/section_file.hpp"
#include "core/error.hpp"
#include "shader/shader_library.hpp"

namespace candela::accuracy {
namespace fs = std::filesystem;

std::vector<Task> plan(const Options& o) {
    const Plan plan = make_plan(o);
    std::vector<Task> tasks;
    for (const Job& j : plan.jobs) tasks.push_back({plan.sweep(j).effect, section_scene(plan.sweep(j), j.scene), job_label(plan, j)});
    return tasks;
}

std::optional<Written> run(const Options& o, Observer& observer) {
    const Plan plan = make_plan(o);
    make_output_dirs(o);
    std::optional<Gl> gl = open_gl(o, observer);
    if (!gl) return std::nullopt;
    const ShaderLibrary shaders(o.shader_dir);
    Progress progress{observer};
    const Sizes z = sizes(o.quick);
    const Run c{o, shaders, z.width, z.height, z.warmup, z.frames, progress};
    for (const Job& j : plan.jobs) progress.total += job_steps(plan.sweep(j), o.quick);
    std::vector<Section> sections;
    std::vector<Row> rows;
    for (const Job& j : plan.jobs) {
        sections.push_back(run_job(c, plan.sweep(j), j.scene, rows));
        sections.back().device = gl->device.device;
        sections.back().backend = gl->device.backend;
    }
    return write_outputs(o, sections, rows, {gl->device}, progress.start);
}

std::optional<SectionDone> run_section(const Options& o, int index, const fs::path& section_dir, Observer& observer) {
    const Plan plan = make_plan(o);
    const int count = static_cast<int>(plan.jobs.size());
    if (index < 0 || index >= count)
        throw bad_input("bench accuracy: --section " + std::to_string(index) + " is out of range: there are " + std::to_string(count) +
                        " sections (0 to " + std::to_string(count - 1) + ", see --list-sections)");
    const Job& j = plan.jobs[static_cast<size_t>(index)];
    const AccuracySweep& s = plan.sweep(j);
    SectionDone done;
    done.label = job_label(plan, j);
    std::string problem;
    if (complete_section(section_dir, o, s, j.scene, problem)) {
        done.skipped = true;
        return done;
    }
    // A stale result goes before any new file is written: a task that dies from here on leaves no
    // section.json, so the directory never looks complete.
    if (fs::exists(section_dir / kSectionFile)) {
        observer.message("note: " + problem + "; running section " + std::to_string(index) + " (" + done.label + ") again");
        fs::remove(section_dir / kSectionFile);
    }
    std::optional<Gl> gl = open_gl(o, observer);
    if (!gl) return std::nullopt;
    const ShaderLibrary shaders(o.shader_dir);
    Progress progress{observer};
    progress.total = job_steps(s, o.quick);
    const Sizes z = sizes(o.quick);
    const Run c{o, shaders, z.width, z.height, z.warmup, z.frames, progress};
    std::vector<Row> rows;
    Section sec = run_job(c, s, j.scene, rows);
    sec.device = gl->device.device;
    sec.backend = gl->device.backend;
    const nlohmann::ordered_json saved = section_json(index, done.label, o, sec, rows);
    save_section(section_dir, saved, sec, rows);
    // Read back what assemble will read: the save must be exact (a full file system or a bad
    // mount shows here, in the task that can be rerun, and not at assembly).
    std::vector<Row> reread_rows;
    const std::optional<nlohmann::json> reread = complete_section(section_dir, o, s, j.scene, problem);
    if (!reread) throw Error(ExitCode::internal, section_dir.string() + ": the saved section does not read back: " + problem);
    const Section copy = load_section(section_dir, *reread, s, reread_rows);
    if (const std::string d = round_trip_difference(sec, rows, copy, reread_rows); !d.empty()) {
        fs::remove(section_dir / kSectionFile);
        throw Error(ExitCode::internal, section_dir.string() + ": the saved section reads back different (" + d + ")");
    }
    done.device = sec.device;
    done.rows = rows.size();
    done.seconds = sec.seconds;
    return done;
}

Written assemble(const Options& o, const std::vector<fs::path>& section_dirs, Observer& observer) {
    const auto start = Clock::now();
    const Plan plan = make_plan(o);
    if (section_dirs.size() != plan.jobs.size())
        throw bad_input("bench accuracy: " + std::to_string(section_dirs.size()) + " section directories given for " +
                        std::to_string(plan.jobs.size()) + " sections (one per section, in --list-sections order)");
    std::vector<Section> sections;
    std::vector<Row> rows;
    int missing = 0;
    for (size_t i = 0; i < plan.jobs.size(); ++i) {
        const Job& j = plan.jobs[i];
        std::string problem;
        try {
            if (const std::optional<nlohmann::json> saved = complete_section(section_dirs[i], o, plan.sweep(j), j.scene, problem))
                sections.push_back(load_section(section_dirs[i], *saved, plan.sweep(j), rows));
        } catch (const std::exception& e) {
            problem = e.what();
        }
        if (!problem.empty()) {
            observer.message(section_dirs[i].string() + ": section " + std::to_string(i) + " (" + job_label(plan, j) +
                             ") is missing or incomplete: " + problem);
            ++missing;
        }
    }
    if (missing > 0)
        throw Error(ExitCode::internal, "bench accuracy: " + std::to_string(missing) + " of " + std::to_string(plan.jobs.size()) +
                                            " sections missing or incomplete; nothing written");
    std::vector<Device> devices;
    for (const Section& sec : sections)
        if (std::find(devices.begin(), devices.end(), Device{sec.device, sec.backend}) == devices.end())
            devices.push_back({sec.device, sec.backend});
    return write_outputs(o, sections, rows, devices, start);
}

}  // namespace candela::accuracy
