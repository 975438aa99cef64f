// Deferred path, second pass: tiled light culling and shading in one compute dispatch
// (shaders/deferred/light.comp). Why tiles rather than light volumes: the G-buffer is read once
// per pixel instead of once per light volume covering it, and there is no per-light draw call or
// stencil state; on llvmpipe, where every byte read is a CPU memory access, that decides it.
#include "render/passes/pass_env.hpp"

namespace candela {

void add_deferred_lighting_pass(FrameGraph& graph, const PassEnv& env, FrameTargets& targets) {
    graph.add_pass(
        "deferred_lighting",
        [&](FrameGraph::Builder& b) {
            for (auto id : targets.gbuffer) b.read(id);
            b.read(targets.depth);
            read_lighting_inputs(b, env);
            b.write(targets.hdr);
        },
        [&env, &targets](FrameGraph::Context& ctx) {
            bind_scene_buffers(env);
            bind_effect_inputs(env, ctx);
            for (int i = 0; i < 3; ++i) {
                glBindTextureUnit(static_cast<GLuint>(i), ctx.texture(targets.gbuffer[i]).id());
                glBindSampler(static_cast<GLuint>(i), 0);
            }
            glBindTextureUnit(3, ctx.texture(targets.depth).id());
            glBindSampler(3, 0);
            glBindImageTexture(0, ctx.texture(targets.hdr).id(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
            ctx.state.use_program(env.programs.get("deferred_light").id());
            glDispatchCompute(static_cast<GLuint>((env.width + 15) / 16), static_cast<GLuint>((env.height + 15) / 16), 1);
            ++ctx.counters.dispatches;
            // Later passes draw into and read the light buffer.
            glMemoryBarrier(GL_FRAMEBUFFER_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT |
                            GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
        });
}

}  // namespace candela
