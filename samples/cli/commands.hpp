#pragma once
// The `candela` command's subcommands. Each returns the process exit code
// (shared/DESIGN.md section 4: 0 ok, 1 internal error, 2 bad input, 3 no usable OpenGL;
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
void print_usage();

}  // namespace candela::cli
