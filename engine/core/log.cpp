#include "core/log.hpp"

#include <atomic>

namespace candela::log {
namespace {
std::atomic<Level> g_level{Level::info};
std::atomic<int> g_warnings{0};
}  // namespace

void set_level(Level level) { g_level = level; }
Level level() { return g_level; }

void warn(const std::string& message) {
    ++g_warnings;
    if (g_level >= Level::warn) std::fprintf(stderr, "candela: warning: %s\n", message.c_str());
}
void info(const std::string& message) {
    if (g_level >= Level::info) std::fprintf(stderr, "candela: %s\n", message.c_str());
}
void debug(const std::string& message) {
    if (g_level >= Level::debug) std::fprintf(stderr, "candela: debug: %s\n", message.c_str());
}
int warning_count() { return g_warnings; }

}  // namespace candela::log
