#pragma once
// Messages for humans go to stderr; stdout is kept for command output (info, compare).
#include <cstdio>
#include <string>

namespace candela::log {

enum class Level { quiet = 0, warn = 1, info = 2, debug = 3 };
void set_level(Level level);
Level level();

void warn(const std::string& message);
void info(const std::string& message);
void debug(const std::string& message);

// Number of warnings emitted so far (tests assert on it).
int warning_count();

}  // namespace candela::log
