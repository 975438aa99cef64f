// Depth of opaque and masked geometry first, so the shading pass runs each pixel once
// (forward.depth_prepass). Masked materials still discard here, through the same program.
#include <glm/gtc/type_ptr.hpp>

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
            ctx.state.bind_vertex_array(env.scene.vertex_array().id());
            // Opaque draws with the program that has no fragment shader work, then the MASK
            // draws with the alpha test; both write the depth of the same gl_Position (invariant
            // in forward.vert), which the shading pass tests EQUAL.
            const GLuint depth_program = env.programs.get("depth_prepass").id();
            ctx.state.use_program(depth_program);
            bool any_masked = false;
            for (const auto& d : env.scene.draws()) {
                any_masked = any_masked || d.alpha_mode == AlphaMode::mask;
                if (d.alpha_mode != AlphaMode::opaque) continue;
                // draw_item without the material's uniforms and textures, which this program does not have.
                ctx.state.set_cull(!d.double_sided, GL_BACK);
                ctx.state.set_front_face(d.mirrored ? GL_CW : GL_CCW);
                glProgramUniformMatrix4fv(depth_program, 0, 1, GL_FALSE, glm::value_ptr(d.model));
                glDrawElementsBaseVertex(GL_TRIANGLES, d.index_count, GL_UNSIGNED_INT,
                                         reinterpret_cast<const void*>(d.first_index * sizeof(std::uint32_t)), d.base_vertex);
                ++ctx.counters.draw_calls;
                ctx.counters.triangles += static_cast<std::size_t>(d.index_count / 3);
            }
            if (!any_masked) return;
            const GLuint mask_program = env.programs.get("depth_prepass_mask").id();
            ctx.state.use_program(mask_program);
            for (const auto& d : env.scene.draws())
                if (d.alpha_mode == AlphaMode::mask) draw_item(env, ctx, d, !d.double_sided, GL_BACK, mask_program, true);
        });
}

}  // namespace candela
