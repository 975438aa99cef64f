// Deferred path, first pass: the surface of every opaque and masked fragment into the G-buffer
// (layout: shaders/lighting/gbuffer.glsl) and its emission into the light buffer.
#include "render/passes/pass_env.hpp"

namespace candela {

void add_gbuffer_pass(FrameGraph& graph, const PassEnv& env, FrameTargets& targets, bool blend_as_opaque) {
    graph.add_pass(
        "gbuffer",
        [&](FrameGraph::Builder& b) {
            b.write(targets.hdr);
            targets.depth = b.create("depth", {GL_DEPTH_COMPONENT32F, env.width, env.height});
            targets.gbuffer[0] = b.create("gbuffer_base_occlusion", {GL_RGBA8, env.width, env.height});
            targets.gbuffer[1] = b.create("gbuffer_normal_roughness_metallic", {GL_RGBA16F, env.width, env.height});
            targets.gbuffer[2] = b.create("gbuffer_f0_f90", {GL_RGBA16F, env.width, env.height});
            targets.normals = targets.gbuffer[1];
        },
        [&env, &targets, blend_as_opaque](FrameGraph::Context& ctx) {
            gl::PipelineState ps;
            ps.depth_test = true;
            ps.depth_func = GL_GREATER;
            ctx.state.apply(ps);
            ctx.state.bind_framebuffer(env.fbos.get({&ctx.texture(targets.gbuffer[0]), &ctx.texture(targets.gbuffer[1]),
                                                     &ctx.texture(targets.gbuffer[2]), &ctx.texture(targets.hdr)},
                                                    &ctx.texture(targets.depth)));
            ctx.state.viewport(0, 0, env.width, env.height);
            const float zero[4] = {0, 0, 0, 0}, black[4] = {0, 0, 0, 1};
            for (int i = 0; i < 3; ++i) glClearBufferfv(GL_COLOR, i, zero);
            glClearBufferfv(GL_COLOR, 3, black);
            const float clear_depth = 0.0f;
            glClearBufferfv(GL_DEPTH, 0, &clear_depth);
            bind_scene_buffers(env);
            const GLuint program = env.programs.get("gbuffer").id();
            ctx.state.use_program(program);
            ctx.state.bind_vertex_array(env.scene.vertex_array().id());
            for (const auto& d : env.scene.draws()) {
                if (d.alpha_mode == AlphaMode::blend && !blend_as_opaque) continue;
                draw_item(env, ctx, d, !d.double_sided, GL_BACK, program);
            }
        });
}

}  // namespace candela
