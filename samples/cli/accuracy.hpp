#pragma once
// `candela bench accuracy` and `candela farm sweep` over the accuracy engine
// (engine/accuracy/accuracy.hpp): the options from the command's arguments, and the engine's
// three entry points with what they print (a progress bar on a terminal, the engine's messages
// on stderr, what was written on stdout) and the exit code.
#include <filesystem>
#include <string>
#include <vector>

#include "accuracy/accuracy.hpp"
#include "commands.hpp"

namespace candela::cli {

// bench accuracy's options from its parsed arguments (scenes, -o, --report, --shader-dir,
// --backend, --effect, --quick, --quiet; bench_accuracy in cmd_bench.cpp); `command` and `args`
// make the command line the report records. Also what `candela farm sweep` tasks run with.
struct Parsed;
accuracy::Options accuracy_options(const Parsed& p, const Args& args, const std::string& command);

// accuracy::run: 0, or 3 without a GL context.
int run_accuracy(const accuracy::Options& options);

// accuracy::run_section: 0 (also when the section was complete and skipped), or 3 without a GL
// context; throws bad_input (2) for an index out of range.
int run_accuracy_section(const accuracy::Options& options, int index, const std::filesystem::path& section_dir);

// accuracy::assemble: 0; a missing or incomplete section: a line naming each, then Error
// internal (exit 1); a wrong number of directories: bad_input (2).
int assemble_accuracy(const accuracy::Options& options, const std::vector<std::filesystem::path>& section_dirs);

}  // namespace candela::cli
