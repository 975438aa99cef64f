#pragma once
// The `candela` command's subcommands, one file each (cmd_render.cpp, cmd_info.cpp, ...; the
// shared option parser and scene set-up are in options.hpp). Each returns the process exit code
// (docs/cli.md: 0 ok, 1 internal error, 2 bad input, 3 no usable OpenGL;
// 4: `compare --check` found images beyond tolerance).
#include <string>
#include <vector>

namespace candela::cli {

using Args = std::vector<std::string>;

int cmd_render(const Args& args);
int cmd_info(const Args& args);
int cmd_compare(const Args& args);
int cmd_bench(const Args& args);
int cmd_merge(const Args& args);
int cmd_shaders(const Args& args);
int cmd_view(const Args& args);
int cmd_batch(const Args& args);  // many render jobs in one process (cmd_batch.cpp)
int cmd_farm(const Args& args);   // tasks for a batch scheduler: Slurm, GNU parallel, ... (cmd_farm.cpp)
int cmd_version(const Args& args);  // `candela --version`: version, git hash, shader directory, GL device
// The --help text (options.cpp).
void print_usage();
// `candela COMMAND --help`: that command's usage lines, its description and the exit codes;
// false for a command the usage does not know.
bool print_command_usage(const std::string& command);

}  // namespace candela::cli
