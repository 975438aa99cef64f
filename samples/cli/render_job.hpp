#pragma once
// `candela batch`: many `render` jobs in one process. What the jobs share: one GL
// context and, per shader directory, one ShaderLibrary and the programs compiled from it (built
// once, reused by every job's renderer; llvmpipe compiles a program's code at its first draw).
// Everything else (scene, GPU scene, renderer, textures) is made and freed per job.
#include <filesystem>
#include <map>
#include <memory>

#include "commands.hpp"
#include "platform/context.hpp"
#include "render/program_cache.hpp"
#include "shader/shader_library.hpp"

namespace candela::cli {

struct BatchSession {
    Context* context = nullptr;  // current for the whole batch
    bool debug = false;          // the context has KHR_debug output: every job checks for GL errors
    bool share_programs = true;  // --no-share-programs (a measurement): each job compiles its own

    struct Programs {
        std::unique_ptr<ShaderLibrary> shaders;
        std::unique_ptr<ProgramCache> cache;
    };
    std::map<std::filesystem::path, Programs> programs;  // by shader directory (--shader-dir)
    Programs& programs_for(const std::filesystem::path& shader_dir) {
        Programs& p = programs[shader_dir];
        if (!p.shaders) {
            p.shaders = std::make_unique<ShaderLibrary>(shader_dir);
            p.cache = std::make_unique<ProgramCache>(*p.shaders);
        }
        return p;
    }
};

// `candela render ARGS`: with `batch`, in the batch's context (a job's --backend must name the
// batch's backend) and with its shared programs; without, in a context of its own.
int run_render(const Args& args, BatchSession* batch);

}  // namespace candela::cli
