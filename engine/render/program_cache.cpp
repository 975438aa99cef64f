#include "render/program_cache.hpp"

#include <algorithm>

#include "core/error.hpp"
#include "render/effect_registry.hpp"
#include "render/program_catalog.hpp"

namespace candela {
namespace {
std::filesystem::path normal(const std::filesystem::path& p) { return std::filesystem::absolute(p).lexically_normal(); }
}  // namespace

ProgramCache::ProgramCache(const ShaderLibrary& shaders) : shaders_(serve_effect_shading(shaders)) {}

const gl::Program& ProgramCache::get(const std::string& name) {
    auto it = programs_.find(name);
    if (it != programs_.end()) return it->second.program;
    const ProgramDesc& desc = program_desc(name);
    ShaderLibrary::BuildResult r = shaders_.build(desc);
    if (!r.ok()) throw Error(ExitCode::internal, "shader program '" + desc.name + "' failed to build:\n" + r.log);
    Entry e;
    e.program = std::move(r.program);
    for (const auto& f : r.files) e.files.insert(normal(f));
    return programs_.emplace(name, std::move(e)).first->second.program;
}

GLuint ProgramCache::id_if_built(const std::string& name) const {
    auto it = programs_.find(name);
    return it == programs_.end() ? 0 : it->second.program.id();
}

ShaderReload ProgramCache::reload(const std::vector<std::filesystem::path>& changed) {
    ShaderReload report;
    std::set<std::filesystem::path> files;
    for (const auto& f : changed) files.insert(normal(f));
    for (auto& [name, entry] : programs_) {
        if (std::none_of(entry.files.begin(), entry.files.end(), [&](const auto& f) { return files.count(f) > 0; })) continue;
        ShaderLibrary::BuildResult r = shaders_.build(program_desc(name));
        for (const auto& f : r.files) entry.files.insert(normal(f));
        if (!r.ok()) {
            report.errors.push_back("shader program '" + name + "' failed to build (keeping the last good one):\n" + r.log);
            continue;
        }
        entry.program = std::move(r.program);
        report.rebuilt.push_back(name);
    }
    return report;
}

}  // namespace candela
