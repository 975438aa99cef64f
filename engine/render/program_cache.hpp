#pragma once
// The renderer's GLSL programs by catalog name (render/program_catalog.hpp, which includes every
// registered effect's programs), built on first request and rebuilt by hot reload.
#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "gl/handles.hpp"
#include "shader/shader_library.hpp"

namespace candela {

// What reload did: programs rebuilt, and messages of those that failed (file:line: ...).
struct ShaderReload {
    std::vector<std::string> rebuilt;
    std::vector<std::string> errors;
};

class ProgramCache {
public:
    // Builds with a copy of `shaders` that serves the effects' shading (serve_effect_shading).
    explicit ProgramCache(const ShaderLibrary& shaders);
    // The program `name`, built now if it is not yet; throws candela::Error (internal) if it does
    // not build. Call at set-up (the renderer builds every planned pass's programs in
    // set_settings), so that a frame only looks programs up.
    const gl::Program& get(const std::string& name);
    // The GL name of `name` if it has been built, else 0 (never builds).
    GLuint id_if_built(const std::string& name) const;
    // Rebuilds every program that includes one of `changed`; a program that fails keeps its last
    // good version. Never throws for GLSL errors.
    ShaderReload reload(const std::vector<std::filesystem::path>& changed);

private:
    struct Entry {
        gl::Program program;
        std::set<std::filesystem::path> files;
    };
    const ShaderLibrary shaders_;
    std::map<std::string, Entry> programs_;  // node-based: references stay valid
};

}  // namespace candela
