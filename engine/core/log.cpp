#include "core/log.hpp"

#include <atomic>
#include <cstdlib>

namespace candela::log {
namespace {
// CANDELA_LOG=quiet|warn|info|debug sets the starting level (default info).
Level initial_level() {
    const char* env = std::getenv("CANDELA_LOG");
    if (!env) return Level::info;
    const std::string v = env;
    return v == "debug" ? Level::debug : v == "warn" ? Level::warn : v == "quiet" ? Level::quiet : Level::info;
}
std::atomic<Level> g_level{initial_level()};
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
