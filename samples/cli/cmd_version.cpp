// `candela --version [--backend B]`: the release (the top-level project() version), the git commit
// it was configured from ("unknown" outside a git checkout), where the shaders are read from, and
// the GL device a context gets. Without usable GL it says so and still exits 0: the version was
// printed, and `candela render` is where "no GL" is an error (exit 3).
#include "commands.hpp"

#include <cstdio>

#include "candela_version.hpp"
#include "core/error.hpp"
#include "options.hpp"
#include "platform/context.hpp"
#include "shader/shader_library.hpp"

namespace candela::cli {

int cmd_version(const Args& args) {
    const Parsed p = parse(args, {"--backend"}, {});
    if (!p.positional.empty()) throw bad_input("--version: unexpected argument '" + p.positional.front() + "'");
    const Backend backend = backend_option(p, true);
    std::printf("candela %s (git %s)\n", kCandelaVersion, kCandelaGitHash);
    std::printf("shaders: %s\n", ShaderLibrary::default_root().string().c_str());
    std::printf("effects: %s\n", ShaderLibrary::default_effects_root().string().c_str());
    std::fflush(stdout);  // before any driver message on stderr
    const ContextResult ctx = create_context(backend);
    if (ctx.context) {
        std::printf("GL: %s (%s)\n", ctx.context->device_string().c_str(), to_string(ctx.context->backend()));
        if (!ctx.notice.empty()) std::printf("GL notice: %s\n", ctx.notice.c_str());
    } else {
        std::printf("GL: unavailable (%s)\n", ctx.error.c_str());
    }
    return 0;
}

}  // namespace candela::cli
