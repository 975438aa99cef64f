// The environment where no geometry was drawn (depth still at the cleared far value, 0).
// Planned only when the scene has an environment: otherwise the cleared black is the answer.
#include "render/passes/pass_env.hpp"

namespace candela {

void add_sky_pass(FrameGraph& graph, const PassEnv& env, FrameTargets& targets) {
    graph.add_pass(
        "sky",
        [&](FrameGraph::Builder& b) {
            b.read(targets.depth);
            b.write(targets.hdr);
        },
        [&env, &targets](FrameGraph::Context& ctx) {
            gl::PipelineState ps;
            ps.depth_test = true;
            ps.depth_func = GL_GEQUAL;  // the full-screen triangle sits at depth 0
            ps.depth_write = false;
            ctx.state.apply(ps);
            ctx.state.bind_framebuffer(env.fbos.get({&ctx.texture(targets.hdr)}, &ctx.texture(targets.depth)));
            ctx.state.viewport(0, 0, env.width, env.height);
            bind_scene_buffers(env);
            ctx.state.use_program(env.programs.get("sky").id());
            ctx.state.bind_vertex_array(env.empty_vao.id());
            glDrawArrays(GL_TRIANGLES, 0, 3);
            ++ctx.counters.draw_calls;
            ctx.counters.triangles += 1;
        });
}

}  // namespace candela
