#pragma once
// A command line held as text (a line of a jobs file: `candela batch`, `candela_golden --jobs`)
// split into arguments.
#include <string>
#include <vector>

namespace candela {

// Whitespace separates arguments, "double quotes" group (\" is a quote inside them), '#' outside
// quotes starts a comment. Throws candela::Error (bad input) on an unbalanced quote.
std::vector<std::string> split_command_line(const std::string& line);

}  // namespace candela
