#pragma once
// The stats JSON of `candela render --stats FILE.json` and `candela bench frame --json`.
#include <filesystem>
#include <string>

#include <nlohmann/json_fwd.hpp>

#include "render/still.hpp"

namespace candela {

struct StatsContext {
    std::string device;   // renderer | version
    std::string backend;
    std::string scene;
};

nlohmann::json stats_json(const StatsContext& context, const StillOptions& options, const StillResult& result);
// Throws candela::Error (bad_input) if the file cannot be written.
void write_json(const std::filesystem::path& path, const nlohmann::json& json);

}  // namespace candela
