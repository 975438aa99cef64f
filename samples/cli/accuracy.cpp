// The CLI side of the accuracy engine (accuracy.hpp): arguments in, text out. The measuring,
// the report and the saved sections are the engine's (engine/accuracy/).
#include "accuracy.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

#include "core/error.hpp"
#include "core/log.hpp"
#include "options.hpp"
#include "shader/shader_library.hpp"

namespace candela::cli {
namespace fs = std::filesystem;

namespace {

// The engine's progress as a bar with an ETA on a terminal's stderr (nothing when stderr is a
// file: logs stay readable); its messages as "candela: ..." lines on stderr.
class Printer : public accuracy::Observer {
public:
    void step(int done, int total, const std::string& what, double seconds) override {
        if (!tty_) return;
        const int width = 30, filled = total > 0 ? std::min(width, done * width / total) : width;
        const double eta = done > 0 ? seconds / done * (total - done) : 0.0;
        std::fprintf(stderr, "\r[%.*s%.*s] %d/%d %-40.40s ETA %.0f s ", filled, "##############################", width - filled,
                     "                              ", done, total, what.c_str(), eta);
        if (done >= total) std::fprintf(stderr, "\n");
    }
    void message(const std::string& text) override { std::fprintf(stderr, "candela: %s\n", text.c_str()); }

private:
    bool tty_ = isatty(STDERR_FILENO) != 0;
};

void print_written(const accuracy::Written& w) {
    std::printf("device: %s\nwrote %s, %s and %zu sections (%zu rows) in %.0f s\n", w.devices.c_str(), w.csv.string().c_str(),
                w.report.string().c_str(), w.sections, w.rows, w.seconds);
}

}  // namespace

accuracy::Options accuracy_options(const Parsed& p, const Args& args, const std::string& command) {
    if (p.flags.count("--quiet")) log::set_level(log::Level::warn);
    accuracy::Options o;
    o.scenes = p.positional;
    for (const std::string& s : o.scenes)
        if (!fs::is_regular_file(s)) throw bad_input(s + ": no such file");
    if (p.has("-o")) o.out = p.get("-o");
    if (p.has("--report")) o.report = p.get("--report");
    o.quick = p.flags.count("--quick") > 0;
    o.effects = p.all("--effect");
    o.shader_dir = shader_dir_option(p);
    // The sample scenes sit beside the built-in shaders in the source tree.
    o.scene_dir = fs::path(ShaderLibrary::default_root()).parent_path() / "samples" / "scenes";
    o.backend = backend_option(p, false);
    o.command_line = command;
    // Absolute paths are recorded by their file name only (the report names no machine's paths).
    for (const std::string& a : args)
        o.command_line += " " + (a.find('/') != std::string::npos && fs::path(a).is_absolute() ? fs::path(a).filename().string() : a);
    return o;
}

int run_accuracy(const accuracy::Options& o) {
    Printer printer;
    const std::optional<accuracy::Written> w = accuracy::run(o, printer);
    if (!w) return static_cast<int>(ExitCode::no_gl);
    print_written(*w);
    return 0;
}

int run_accuracy_section(const accuracy::Options& o, int index, const fs::path& section_dir) {
    Printer printer;
    const std::optional<accuracy::SectionDone> d = accuracy::run_section(o, index, section_dir, printer);
    if (!d) return static_cast<int>(ExitCode::no_gl);
    if (d->skipped)
        std::printf("section %d (%s): %s is complete, skipped\n", index, d->label.c_str(), section_dir.string().c_str());
    else
        std::printf("device: %s\nsection %d (%s): wrote %s (%zu rows) in %.1f s\n", d->device.c_str(), index, d->label.c_str(),
                    section_dir.string().c_str(), d->rows, d->seconds);
    return 0;
}

int assemble_accuracy(const accuracy::Options& o, const std::vector<fs::path>& section_dirs) {
    Printer printer;
    print_written(accuracy::assemble(o, section_dirs, printer));
    return 0;
}

}  // namespace candela::cli
