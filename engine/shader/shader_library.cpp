#include "shader/shader_library.hpp"

#include <unistd.h>

#include <climits>
#include <cstdlib>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>

#include "core/error.hpp"

#ifndef CANDELA_SHADER_DIR
#define CANDELA_SHADER_DIR "shaders"
#endif
#ifndef CANDELA_EFFECTS_DIR
#define CANDELA_EFFECTS_DIR "engine"
#endif

namespace candela {
namespace fs = std::filesystem;

namespace {

std::string read_text(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        std::error_code ec;
        const std::string where = fs::exists(path, ec) ? ""
                                  : " (shaders are read from CANDELA_SHADER_DIR and CANDELA_EFFECTS_DIR, else from "
                                    "<prefix>/share/candela beside an installed candela, else from the source tree; "
                                    "docs/install.md)";
        throw Error(ExitCode::internal, path.string() + ": cannot open shader file" + where);
    }
    std::ostringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

GLenum gl_stage(ShaderStage stage) {
    switch (stage) {
        case ShaderStage::vertex: return GL_VERTEX_SHADER;
        case ShaderStage::fragment: return GL_FRAGMENT_SHADER;
        case ShaderStage::compute: return GL_COMPUTE_SHADER;
    }
    return GL_VERTEX_SHADER;
}

using Generated = std::map<std::string, ShaderLibrary::GeneratedInclude>;


struct Expander {
    const ShaderLibrary& lib;
    const Generated& generated;
    std::function<fs::path(const fs::path&, const std::string&)> resolve;
    PreprocessedSource out;
    std::set<fs::path> included;
    std::vector<fs::path> stack;

    int file_id(const fs::path& p) {
        for (size_t i = 0; i < out.files.size(); ++i)
            if (out.files[i] == p) return static_cast<int>(i);
        out.files.push_back(p.lexically_normal());
        return static_cast<int>(out.files.size()) - 1;
    }

    // Appends `file` (already past its #version line if `skip_version`).
    void expand(const fs::path& file, bool is_main, const std::vector<std::string>& defines) {
        const fs::path canonical = fs::weakly_canonical(file);
        for (const fs::path& f : stack)
            if (f == canonical) throw Error(ExitCode::internal, file.string() + ": #include cycle");
        if (!is_main && included.count(canonical)) return;
        included.insert(canonical);
        stack.push_back(canonical);
        const int id = file_id(file);
        std::istringstream in(read_text(file));
        std::string line;
        int line_no = 0;
        bool version_seen = !is_main;
        static const std::regex include_re(R"(^\s*#\s*include\s*"([^"]+)\"\s*$)");
        static const std::regex version_re(R"(^\s*#\s*version\b.*)");
        if (!is_main) out.text += "#line 1 " + std::to_string(id) + "\n";
        while (std::getline(in, line)) {
            ++line_no;
            std::smatch m;
            if (!version_seen && std::regex_match(line, version_re)) {
                out.text += line + "\n";
                for (const std::string& d : defines) out.text += "#define " + d + "\n";
                out.text += "#line " + std::to_string(line_no + 1) + " " + std::to_string(id) + "\n";
                version_seen = true;
            } else if (std::regex_match(line, m, include_re)) {
                const auto g = generated.find(m[1].str());
                const std::vector<std::string> names = g != generated.end() ? g->second.files : std::vector<std::string>{m[1].str()};
                for (const std::string& name : names) {
                    const fs::path inc = resolve(file.parent_path(), name);
                    if (inc.empty())
                        throw Error(ExitCode::internal, file.string() + ":" + std::to_string(line_no) + ": cannot find include \"" +
                                                            name + "\"");
                    expand(inc, false, {});
                }
                if (g != generated.end() && !g->second.text.empty() && included.insert(fs::path(g->first + " (generated)")).second) {
                    out.text += "#line 1 " + std::to_string(file_id(g->first + " (generated)")) + "\n" + g->second.text;
                    if (g->second.text.back() != '\n') out.text += "\n";
                }
                out.text += "#line " + std::to_string(line_no + 1) + " " + std::to_string(id) + "\n";
            } else {
                out.text += line + "\n";
            }
        }
        if (!version_seen) throw Error(ExitCode::internal, file.string() + ": no #version line");
        stack.pop_back();
    }
};

}  // namespace

std::string PreprocessedSource::map_log(const std::string& log) const {
    // Mesa: "0:12(3): error: ..."; glslang: "ERROR: 0:12: ..."; NVIDIA: "0(12) : error ...".
    static const std::regex re(R"((\d+)[:(](\d+)(\(\d+\))?\)?\s*:)");
    std::string result;
    std::istringstream in(log);
    for (std::string line; std::getline(in, line);) {
        std::smatch m;
        if (std::regex_search(line, m, re)) {
            const size_t id = std::stoul(m[1].str());
            if (id < files.size()) {
                line = m.prefix().str() + files[id].string() + ":" + m[2].str() + ":" + m.suffix().str();
            }
        }
        result += line + "\n";
    }
    return result;
}

ShaderLibrary::ShaderLibrary(fs::path root, fs::path effects_root)
    : root_(std::move(root)), effects_root_(std::move(effects_root)) {}

void ShaderLibrary::set_generated_include(const std::string& name, std::vector<std::string> files, std::string text) {
    generated_[name] = GeneratedInclude{std::move(files), std::move(text)};
}


fs::path ShaderLibrary::installed_data_dir() {
    char buf[PATH_MAX];
    const ssize_t n = readlink("/proc/self/exe", buf, sizeof buf - 1);
    if (n <= 0) return {};
    buf[n] = '\0';
    // <prefix>/bin/candela -> <prefix>/share/candela (cmake --install, the .deb's /usr).
    const fs::path dir = fs::path(buf).parent_path().parent_path() / "share" / "candela";
    std::error_code ec;
    return fs::is_directory(dir / "shaders", ec) ? dir : fs::path();
}

fs::path ShaderLibrary::default_effects_root() {
    if (const char* env = std::getenv("CANDELA_EFFECTS_DIR"); env && *env) return env;
    if (fs::path installed = installed_data_dir(); !installed.empty()) return installed;
    return CANDELA_EFFECTS_DIR;
}

std::vector<fs::path> ShaderLibrary::watched_dirs() const {
    std::vector<fs::path> dirs = {root_};
    if (fs::is_directory(effects_root_ / "effects")) dirs.push_back(effects_root_ / "effects");
    if (fs::is_directory(effects_root_ / "gpu")) dirs.push_back(effects_root_ / "gpu");  // the shared blocks
    return dirs;
}

fs::path ShaderLibrary::default_root() {
    if (const char* env = std::getenv("CANDELA_SHADER_DIR"); env && *env) return env;
    if (fs::path installed = installed_data_dir(); !installed.empty()) return installed / "shaders";
    return CANDELA_SHADER_DIR;
}

fs::path ShaderLibrary::resolve(const fs::path& including_dir, const std::string& name) const {
    for (const fs::path& dir : {including_dir, root_, effects_root_}) {
        const fs::path p = dir / name;
        if (fs::is_regular_file(p)) return p;
    }
    return {};
}

PreprocessedSource ShaderLibrary::preprocess(const fs::path& file, const std::vector<std::string>& defines) const {
    const fs::path path = file.is_absolute()                      ? file
                          : fs::exists(root_ / file) || effects_root_.empty() ? root_ / file
                                                                               : effects_root_ / file;
    Expander ex{*this, generated_, [this](const fs::path& d, const std::string& n) { return resolve(d, n); }, {}, {}, {}};
    ex.expand(path, true, defines);
    return std::move(ex.out);
}

ShaderLibrary::BuildResult ShaderLibrary::build(const ProgramDesc& desc) const {
    BuildResult result;
    std::vector<gl::Shader> shaders;
    bool ok = true;
    for (const auto& [stage, file] : desc.stages) {
        PreprocessedSource src;
        try {
            src = preprocess(file, desc.defines);
        } catch (const Error& e) {
            result.log += std::string(e.what()) + "\n";
            ok = false;
            continue;
        }
        result.files.insert(result.files.end(), src.files.begin(), src.files.end());
        gl::Shader shader(glCreateShader(gl_stage(stage)));
        const char* text = src.text.c_str();
        glShaderSource(shader.id(), 1, &text, nullptr);
        glCompileShader(shader.id());
        GLint status = 0, length = 0;
        glGetShaderiv(shader.id(), GL_COMPILE_STATUS, &status);
        glGetShaderiv(shader.id(), GL_INFO_LOG_LENGTH, &length);
        if (!status) {
            std::string log(static_cast<size_t>(std::max(length, 1)), '\0');
            glGetShaderInfoLog(shader.id(), length, nullptr, log.data());
            // Mesa reports source string 0 for semantic errors in included files (right line,
            // wrong file); glslang keeps the #line source numbers, so its messages lead.
            const std::string glslang = validate_with_glslang(src, stage);
            if (!glslang.empty()) result.log += glslang + "(driver: " + src.map_log(log.c_str()) + ")\n";
            else result.log += src.map_log(log.c_str());
            ok = false;
        }
        shaders.push_back(std::move(shader));
    }
    if (!ok) return result;
    gl::Program program(glCreateProgram());
    for (const gl::Shader& s : shaders) glAttachShader(program.id(), s.id());
    glLinkProgram(program.id());
    GLint status = 0, length = 0;
    glGetProgramiv(program.id(), GL_LINK_STATUS, &status);
    if (!status) {
        glGetProgramiv(program.id(), GL_INFO_LOG_LENGTH, &length);
        std::string log(static_cast<size_t>(std::max(length, 1)), '\0');
        glGetProgramInfoLog(program.id(), length, nullptr, log.data());
        result.log += desc.name + ": link failed: " + log.c_str();
        return result;
    }
    for (const gl::Shader& s : shaders) glDetachShader(program.id(), s.id());
    result.program = std::move(program);
    return result;
}

gl::Program ShaderLibrary::build_or_throw(const ProgramDesc& desc) const {
    BuildResult r = build(desc);
    if (!r.ok()) throw Error(ExitCode::internal, "shader program '" + desc.name + "' failed to build:\n" + r.log);
    return std::move(r.program);
}

}  // namespace candela
