#pragma once
// GLSL sources from shaders/: #include "file.glsl" resolved (relative to the including file, then
// to the shader root), each file included once, #line directives so that compiler messages map
// back to file:line, and defines injected after #version. Programs remember their files so the
// hot reloader knows what to rebuild. A generated include (set_generated_include) stands for a
// list of includes and text given by the code that knows them (the effects registry gives
// "effects_shading.glsl": what each effect adds to the lighting code).
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "gl/handles.hpp"

namespace candela {

enum class ShaderStage { vertex, fragment, compute };

struct PreprocessedSource {
    std::string text;
    std::vector<std::filesystem::path> files;  // index = the source-string number used in #line
    // Rewrites "0:12(3): error: ..." (Mesa) or "0(12) : error" (others) into "file.glsl:12: ...".
    std::string map_log(const std::string& log) const;
};

struct ProgramDesc {
    std::string name;  // for messages
    std::vector<std::pair<ShaderStage, std::filesystem::path>> stages;  // relative to the root
    std::vector<std::string> defines;  // "NAME" or "NAME VALUE"
};

class ShaderLibrary {
public:
    // `root`: the shared GLSL (shaders/); `effects_root`: the directory holding effects/ (the
    // source tree's engine/), where each effect keeps its GLSL beside its C++. A file or an
    // #include is looked up relative to the including file, then in `root`, then in `effects_root`,
    // so "effects/ssao/ssao_data.h" and "gpu/scene_blocks.h" name the same file from C++ and GLSL.
    explicit ShaderLibrary(std::filesystem::path root, std::filesystem::path effects_root = default_effects_root());
    // The directory from CANDELA_SHADER_DIR in the environment, else the installed shaders/ beside
    // the executable (installed_data_dir()), else the source tree's shaders/.
    static std::filesystem::path default_root();
    // CANDELA_EFFECTS_DIR in the environment, else installed_data_dir() (which holds effects/ and
    // gpu/), else the source tree's engine/.
    static std::filesystem::path default_effects_root();
    // An installed Candela's data: <prefix>/share/candela for an executable in <prefix>/bin, if it
    // holds shaders/ (docs/install.md); empty otherwise (a build tree, another program's directory).
    static std::filesystem::path installed_data_dir();

    const std::filesystem::path& root() const { return root_; }
    const std::filesystem::path& effects_root() const { return effects_root_; }
    // The directories whose files programs are built from (what hot reload watches): root(),
    // effects_root()/effects and effects_root()/gpu (the blocks and bindings shared with C++).
    std::vector<std::filesystem::path> watched_dirs() const;
    // `#include "name"` in any file then includes each of `files`, in order, resolved like any
    // include, then `text` (compiler messages name it "name (generated)"). A library starts with
    // none: the renderer's programs get the effects' shading (serve_effect_shading,
    // render/effect_registry.hpp).
    void set_generated_include(const std::string& name, std::vector<std::string> files, std::string text = {});
    struct GeneratedInclude {
        std::vector<std::string> files;
        std::string text;
    };
    // Throws candela::Error (internal) with "file:line: message" on a missing file or include cycle.
    PreprocessedSource preprocess(const std::filesystem::path& file, const std::vector<std::string>& defines) const;

    struct BuildResult {
        gl::Program program;  // empty on failure
        std::string log;      // mapped compiler/linker messages
        std::vector<std::filesystem::path> files;
        bool ok() const { return static_cast<bool>(program); }
    };
    // Compiles and links with the current GL context; never throws for GLSL errors.
    BuildResult build(const ProgramDesc& desc) const;
    // build() that throws candela::Error (internal) on failure: for the engine's own programs.
    gl::Program build_or_throw(const ProgramDesc& desc) const;

private:
    std::filesystem::path resolve(const std::filesystem::path& including_dir, const std::string& name) const;
    std::filesystem::path root_;
    std::filesystem::path effects_root_;
    std::map<std::string, GeneratedInclude> generated_;
};

// Offline check with glslang (no GL context needed): empty string if the source compiles and its
// stage links on its own as GLSL 4.50 core, else glslang's messages mapped through `source.map_log`.
std::string validate_with_glslang(const PreprocessedSource& source, ShaderStage stage);

}  // namespace candela
