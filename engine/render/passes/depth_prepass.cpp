// Depth of opaque and masked geometry first, so the shading pass runs each pixel once
// (forward.depth_prepass). Masked materials still discard here, through the same program.
#include "render/passes/pass_env.hpp"

namespace candela {

void add_depth_prepass(FrameGraph& graph, const PassEnv& env, FrameTargets& targets) {
    graph.add_pass(
        "depth_prepass",
        [&](FrameGraph::Builder& b) {
            targets.depth = b.create(targets.samples > 1 ? "depth_aa" : "depth",
                                     {GL_DEPTH_COMPONENT32F, env.width, env.height, targets.samples});
        },
        [&env, &targets](FrameGraph::Context& ctx) {
            gl::PipelineState ps;
            ps.depth_test = true;
            ps.color_write = false;
            ctx.state.apply(ps);
            ctx.state.bind_framebuffer(env.fbos.get({}, &ctx.texture(targets.depth)));
            ctx.state.viewport(0, 0, env.width, env.height);
            const float clear_depth = 0.0f;  // reversed-Z far
            glClearBufferfv(GL_DEPTH, 0, &clear_depth);
            bind_scene_buffers(env);
            ctx.state.use_program(env.programs.get("forward").id());
            ctx.state.bind_vertex_array(env.scene.vertex_array().id());
            for (const auto& d : env.scene.draws())
                if (d.alpha_mode != AlphaMode::blend) draw_item(env, ctx, d, !d.double_sided, GL_BACK);
        });
}

}  // namespace candela
