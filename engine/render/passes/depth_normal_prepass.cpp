// The forward path's depth + normal prepass, when a planned effect reads the camera's depth and
// normals before shading (Effect::needs_depth_normals: SSAO, RSM): the shading normal,
// octahedral as the G-buffer stores it, so those effects read the same input on both paths. The
// shading pass then runs with depth test EQUAL.
#include "render/passes/pass_env.hpp"

namespace candela {

void add_depth_normal_prepass(FrameGraph& graph, const PassEnv& env, FrameTargets& targets, bool blend_as_opaque) {
    targets.prepass_has_blend = blend_as_opaque;
    // Its own ids (a multisampled shading pass replaces targets.depth after it).
    struct Data {
        FrameGraph::ResourceId depth = -1, normals = -1;
    };
    graph.add_pass<Data>(
        "depth_normal_prepass",
        [&](FrameGraph::Builder& b, Data& d) {
            d.depth = targets.depth = b.create("depth", {GL_DEPTH_COMPONENT32F, env.width, env.height});
            d.normals = targets.normals = b.create("normals", {GL_RG16F, env.width, env.height});
        },
        [&env, blend_as_opaque](const Data& targets, FrameGraph::Context& ctx) {
            gl::PipelineState ps;
            ps.depth_test = true;
            ctx.state.apply(ps);
            ctx.state.bind_framebuffer(env.fbos.get({&ctx.texture(targets.normals)}, &ctx.texture(targets.depth)));
            ctx.state.viewport(0, 0, env.width, env.height);
            const float zero[4] = {0, 0, 0, 0};
            glClearBufferfv(GL_COLOR, 0, zero);
            const float clear_depth = 0.0f;
            glClearBufferfv(GL_DEPTH, 0, &clear_depth);
            bind_scene_buffers(env);
            const GLuint program = env.programs.get("depth_normals").id();
            ctx.state.use_program(program);
            ctx.state.bind_vertex_array(env.scene.vertex_array().id());
            for (const auto& d : env.scene.draws())
                if (d.alpha_mode != AlphaMode::blend || blend_as_opaque) draw_item(env, ctx, d, !d.double_sided, GL_BACK, program);
        });
}

}  // namespace candela
