// `candela shaders check`: every program and ray-tracer variant through glslang and the GL driver.
#include "commands.hpp"

#include <cstdio>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/log.hpp"
#include "options.hpp"
#include "render/effect_registry.hpp"
#include "render/program_catalog.hpp"
#include "shader/shader_library.hpp"

namespace candela::cli {

int cmd_shaders(const Args& args) {
    const Parsed p = parse(args, {"--shader-dir", "--backend"}, {"--quiet"});
    if (p.positional.size() != 1 || p.positional[0] != "check") throw bad_input("usage: candela shaders check [--shader-dir DIR] [--backend B]");
    if (p.flags.count("--quiet")) log::set_level(log::Level::warn);
    SceneSetup s;
    s.shader_dir = shader_dir_option(p);
    s.backend = backend_option(p, false);
    const ShaderLibrary shaders = serve_effect_shading(ShaderLibrary(s.shader_dir));
    std::vector<ProgramDesc> programs = raster_programs();
    for (ProgramDesc& d : ray_tracer_variants()) programs.push_back(std::move(d));
    // glslang first: it needs no GL, so a machine without GL still checks the sources.
    int failed = 0;
    std::vector<bool> glslang_ok(programs.size(), true);
    for (size_t i = 0; i < programs.size(); ++i) {
        for (const auto& [stage, file] : programs[i].stages) {
            std::string problem;
            try {
                problem = validate_with_glslang(shaders.preprocess(file, programs[i].defines), stage);
            } catch (const Error& e) {
                problem = e.what();
            }
            if (!problem.empty()) {
                std::printf("FAIL glslang %s (%s):\n%s\n", programs[i].name.c_str(), file.string().c_str(), problem.c_str());
                glslang_ok[i] = false;
            }
        }
        failed += !glslang_ok[i];
    }
    ContextResult ctx = open_context(s);
    if (!ctx.context) {
        std::printf("%zu programs: %d failed glslang; no GL context for the driver check\n", programs.size(), failed);
        return static_cast<int>(failed ? ExitCode::internal : ExitCode::no_gl);
    }
    for (size_t i = 0; i < programs.size(); ++i) {
        const ShaderLibrary::BuildResult r = shaders.build(programs[i]);
        if (r.ok() && glslang_ok[i]) std::printf("ok   %s\n", programs[i].name.c_str());
        if (!r.ok()) {
            std::printf("FAIL driver %s:\n%s\n", programs[i].name.c_str(), r.log.c_str());
            failed += glslang_ok[i];
        }
    }
    std::printf("%zu programs (glslang and %s): %d failed\n", programs.size(), ctx.context->device_string().c_str(), failed);
    return failed ? static_cast<int>(ExitCode::internal) : 0;
}

}  // namespace candela::cli
