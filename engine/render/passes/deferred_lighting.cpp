// Deferred path, second pass: tiled light culling and shading in one compute dispatch
// (shaders/deferred/light.comp). Why tiles rather than light volumes: the G-buffer is read once
// per pixel instead of once per light volume covering it, and there is no per-light draw call or
// stencil state; on llvmpipe, where every byte read is a CPU memory access, that decides it.
// With a multisampled G-buffer (FrameSampling::samples > 1) the "deferred_light_ms" variant shades a pixel
// once where its samples see one surface and, at the edge pixels, once per surface they show
// (deferred_light_ms_edges shades the further surfaces in a second, indirect dispatch).
#include "render/passes/deferred_lighting.hpp"

#include <cstdio>
#include <cstdlib>
#include <mutex>

#include "core/log.hpp"
#include "render/effect.hpp"
#include "gpu/bindings.h"
#include "render/passes/pass_env.hpp"

namespace candela {
namespace {

std::mutex g_stats_mutex;
DeferredEdgeStats g_stats;

bool count_edges() {
    const char* v = std::getenv("CANDELA_AA_STATS");
    return v && *v && *v != '0';
}

// The frame's sample positions (FrameSampling::positions), [0,1] in the pixel, y up (as
// gl_SamplePosition), flattened x, y for the shader's uniform.
std::vector<float> flat_positions(const FrameSampling& sampling) {
    std::vector<float> positions;
    for (const glm::vec2& p : sampling.positions) {
        positions.push_back(p.x + 0.5f);
        positions.push_back(p.y + 0.5f);
    }
    return positions;
}

}  // namespace

DeferredEdgeStats last_deferred_edge_stats() {
    std::lock_guard<std::mutex> lock(g_stats_mutex);
    return g_stats;
}

void add_deferred_lighting_pass(FrameGraph& graph, const PassEnv& env, FrameTargets& targets) {
    struct Data {
        FrameGraph::ResourceId gbuffer[3] = {-1, -1, -1}, depth = -1, hdr = -1;
        FrameGraph::ResourceId edge_groups = -1;  // multisampled: the edge pixels' further sample groups
    };
    const int n = targets.samples;
    graph.add_pass<Data>(
        "deferred_lighting",
        [&](FrameGraph::Builder& b, Data& d) {
            for (int i = 0; i < 3; ++i) d.gbuffer[i] = b.read(targets.gbuffer[i], static_cast<unsigned>(GBUFFER_BASE_UNIT + i));
            d.depth = b.read(targets.gbuffer_depth, GBUFFER_DEPTH_UNIT);
            read_lighting_inputs(b, env);
            d.hdr = b.write(targets.hdr);
            // Room for N - 1 further groups per pixel (the most a pixel can have).
            if (n > 1) d.edge_groups = b.create("edge_groups", {GL_RG32UI, env.width, env.height * (n - 1)});
            // The passes after this one draw into the light buffer over the G-buffer's depth
            // (multisampled: not the single-sample copy the screen-space passes read).
            targets.depth = targets.gbuffer_depth;
        },
        [&env, n, positions = flat_positions(env.sampling)](const Data& d, FrameGraph::Context& ctx) {
            bind_scene_buffers(env);
            bind_effect_inputs(env, ctx);
            glBindImageTexture(LIGHT_BUFFER_IMAGE, ctx.texture(d.hdr).id(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
            const bool ms = n > 1;
            const GLuint program =
                env.programs.get(deferred_light_program_name(env, ms ? "deferred_light_ms" : "deferred_light")).id();
            ctx.state.use_program(program);
            GLuint stats = 0;
            if (ms) {
                glProgramUniform2fv(program, 1, n, positions.data());
                const bool count = count_edges();
                glProgramUniform1i(program, 0, count ? 1 : 0);
                if (count) {
                    const GLuint zero[3] = {0, 0, 0};
                    glCreateBuffers(1, &stats);
                    glNamedBufferStorage(stats, sizeof(zero), zero, 0);
                    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, AA_EDGE_STATS_BINDING, stats);
                }
            }
            GLuint edge_dispatch = 0;
            if (ms) {
                // The list's count and the indirect dispatch's arguments (x = ceil(count / 64)).
                const GLuint args[4] = {0, 1, 1, 0};
                glCreateBuffers(1, &edge_dispatch);
                glNamedBufferStorage(edge_dispatch, sizeof(args), args, 0);
                glBindBufferBase(GL_SHADER_STORAGE_BUFFER, EDGE_DISPATCH_BINDING, edge_dispatch);
                glBindImageTexture(EDGE_GROUPS_IMAGE, ctx.texture(d.edge_groups).id(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_RG32UI);
            }
            glDispatchCompute(static_cast<GLuint>((env.width + 15) / 16), static_cast<GLuint>((env.height + 15) / 16), 1);
            ++ctx.counters.dispatches;
            if (ms) {
                // The further sample groups of the edge pixels, one invocation each.
                glMemoryBarrier(GL_COMMAND_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
                const GLuint edges = env.programs.get(deferred_light_program_name(env, "deferred_light_ms_edges")).id();
                ctx.state.use_program(edges);
                glProgramUniform2fv(edges, 1, n, positions.data());
                glProgramUniform1i(edges, 0, 0);
                glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, edge_dispatch);
                glDispatchComputeIndirect(0);
                glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, 0);
                glBindBufferBase(GL_SHADER_STORAGE_BUFFER, EDGE_DISPATCH_BINDING, 0);
                glBindImageTexture(EDGE_GROUPS_IMAGE, 0, 0, GL_FALSE, 0, GL_READ_WRITE, GL_RG32UI);
                glDeleteBuffers(1, &edge_dispatch);  // freed once the dispatch is done with it
                ++ctx.counters.dispatches;
            }
            // Later passes draw into and read the light buffer.
            glMemoryBarrier(GL_FRAMEBUFFER_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT |
                            GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
            if (stats) {
                // A debug readback (CANDELA_AA_STATS=1): waits for the dispatch.
                glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
                GLuint counts[3] = {0, 0, 0};
                glGetNamedBufferSubData(stats, 0, sizeof(counts), counts);
                glBindBufferBase(GL_SHADER_STORAGE_BUFFER, AA_EDGE_STATS_BINDING, 0);
                glDeleteBuffers(1, &stats);
                {
                    std::lock_guard<std::mutex> lock(g_stats_mutex);
                    g_stats = {static_cast<long long>(counts[0]), static_cast<long long>(counts[1]),
                               static_cast<long long>(counts[2]), n};
                }
                char line[256];
                std::snprintf(line, sizeof line,
                              "deferred_lighting: %u of %u pixels with geometry shaded more than once (%.2f %%), "
                              "%.4f shadings per pixel, %d samples",
                              counts[0], counts[1], counts[1] ? 100.0 * counts[0] / counts[1] : 0.0,
                              counts[1] ? static_cast<double>(counts[2]) / counts[1] : 0.0, n);
                log::info(line);
            }
        });
}

}  // namespace candela
