#include "render/stats.hpp"

#include <fstream>

#include <nlohmann/json.hpp>

#include "core/error.hpp"

namespace candela {

nlohmann::json stats_json(const StatsContext& c, const StillOptions& o, const StillResult& r) {
    nlohmann::json j;
    j["device"] = c.device;
    j["backend"] = c.backend;
    j["scene"] = c.scene;
    j["resolution"] = {o.width, o.height};
    j["settings"] = to_json(o.settings);
    j["features"] = to_json(r.features);
    const auto [q1, q3] = quartiles(r.frame_ms);
    j["frames"] = {{"measured", o.frames}, {"warmup", o.warmup}, {"median_ms", r.median_frame_ms()},
                   {"iqr_ms", {q1, q3}}, {"all_ms", r.frame_ms}};
    j["graph_ms"] = r.report.graph_ms;
    j["pool"] = {{"allocations", r.report.pool_allocations}, {"slots", r.report.pool_slots}};
    j["state_calls"] = {{"real", r.report.state_calls}, {"skipped", r.report.state_calls_skipped}};
    j["passes"] = nlohmann::json::array();
    for (const PassStats& p : r.report.passes)
        j["passes"].push_back({{"name", p.name}, {"gpu_ms", p.gpu_ms}, {"cpu_ms", p.cpu_ms},
                               {"draw_calls", p.counters.draw_calls}, {"triangles", p.counters.triangles},
                               {"dispatches", p.counters.dispatches}});
    j["culled_passes"] = nlohmann::json::array();
    for (const auto& [name, reason] : r.report.culled) j["culled_passes"].push_back({{"name", name}, {"reason", reason}});
    j["setup_ms"] = {{"upload", r.upload_ms}, {"shaders", r.shader_ms}, {"readback", r.readback_ms}};
    return j;
}

void write_json(const std::filesystem::path& path, const nlohmann::json& json) {
    std::ofstream out(path);
    if (!out) throw bad_input(path.string() + ": cannot write");
    out << json.dump(2) << "\n";
    if (!out) throw bad_input(path.string() + ": write failed");
}

}  // namespace candela
