// Alpha-blended geometry after everything opaque: back to front by the view depth of each
// draw's bounds centre, SRC_ALPHA / ONE_MINUS_SRC_ALPHA, depth test on and depth write off;
// double-sided meshes draw their back faces first.
#include <algorithm>

#include "render/passes/pass_env.hpp"

namespace candela {

void add_transparent_pass(FrameGraph& graph, const PassEnv& env, ForwardTargets& targets) {
    graph.add_pass(
        "transparent",
        [&](FrameGraph::Builder& b) {
            b.read(targets.depth);
            if (targets.shadow_maps >= 0) b.read(targets.shadow_maps);
            if (targets.ssao >= 0) b.read(targets.ssao);
            if (targets.rsm_indirect >= 0) b.read(targets.rsm_indirect);
            b.write(targets.hdr);
        },
        [&env, &targets](FrameGraph::Context& ctx) {
            std::vector<const GpuScene::Draw*> blended;
            for (const auto& d : env.scene.draws())
                if (d.alpha_mode == AlphaMode::blend) blended.push_back(&d);
            auto view_depth = [&](const GpuScene::Draw* d) {
                return (env.frame.view * glm::vec4(d->world_bounds.center(), 1.0f)).z;  // more negative = farther
            };
            std::stable_sort(blended.begin(), blended.end(), [&](auto* a, auto* b) { return view_depth(a) < view_depth(b); });
            gl::PipelineState ps;
            ps.depth_test = true;
            ps.depth_write = false;
            ps.blend = true;
            ps.blend_src_rgb = GL_SRC_ALPHA;
            ps.blend_dst_rgb = GL_ONE_MINUS_SRC_ALPHA;
            ps.blend_src_alpha = GL_ZERO;
            ps.blend_dst_alpha = GL_ONE;
            ctx.state.apply(ps);
            ctx.state.bind_framebuffer(env.fbos.get({&ctx.texture(targets.hdr)}, &ctx.texture(targets.depth)));
            ctx.state.viewport(0, 0, env.width, env.height);
            bind_scene_buffers(env);
            bind_ssao(env, ctx, targets);
            ctx.state.use_program(env.programs.forward.id());
            ctx.state.bind_vertex_array(env.scene.vertex_array().id());
            for (const auto* d : blended) {
                if (d->double_sided) draw_item(env, ctx, *d, true, GL_FRONT);
                draw_item(env, ctx, *d, true, GL_BACK);
            }
        });
}

}  // namespace candela
