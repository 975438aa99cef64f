// Forward shading of opaque and alpha-masked geometry into the linear HDR target.
#include "render/passes/pass_env.hpp"

namespace candela {

void add_forward_opaque_pass(FrameGraph& graph, const PassEnv& env, FrameTargets& targets, bool blend_as_opaque) {
    const bool prepass = targets.depth >= 0;
    graph.add_pass(
        "forward_opaque",
        [&](FrameGraph::Builder& b) {
            b.write(targets.hdr);
            read_lighting_inputs(b, env);
            if (prepass) b.read(targets.depth);
            else targets.depth = b.create("depth", {GL_DEPTH_COMPONENT32F, env.width, env.height});
        },
        [&env, &targets, prepass, blend_as_opaque](FrameGraph::Context& ctx) {
            gl::PipelineState ps;
            ps.depth_test = true;
            // After a prepass the depth is final: shade only the visible surface.
            ps.depth_func = prepass ? GL_EQUAL : GL_GREATER;
            ps.depth_write = !prepass;
            ctx.state.apply(ps);
            ctx.state.bind_framebuffer(env.fbos.get({&ctx.texture(targets.hdr)}, &ctx.texture(targets.depth)));
            ctx.state.viewport(0, 0, env.width, env.height);
            const float clear_color[4] = {0, 0, 0, 1};
            glClearBufferfv(GL_COLOR, 0, clear_color);
            if (!prepass) {
                const float clear_depth = 0.0f;
                glClearBufferfv(GL_DEPTH, 0, &clear_depth);
            }
            bind_scene_buffers(env);
            bind_effect_inputs(env, ctx);
            ctx.state.use_program(env.programs.get("forward").id());
            ctx.state.bind_vertex_array(env.scene.vertex_array().id());
            for (const auto& d : env.scene.draws()) {
                // Without the transparency effect, blended materials are drawn as opaque ones
                // (after a prepass that skipped them they would fail the EQUAL test, so skip).
                if (d.alpha_mode == AlphaMode::blend && (!blend_as_opaque || (prepass && !targets.prepass_has_blend))) continue;
                draw_item(env, ctx, d, !d.double_sided, GL_BACK);
            }
        });
}

}  // namespace candela
