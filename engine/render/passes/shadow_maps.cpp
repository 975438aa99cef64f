// Shadow maps: the depth of every caster from each shadow view (render/shadows.hpp), one layer of
// the shadow array per view. Casters are drawn without face culling (closed or not, both sides
// cast) and with slope-scaled polygon offset away from the light; an area-light piece's own
// emitter does not shadow it. BLEND materials cast like opaque ones, as they block rays in the
// ray tracer.
#include <glm/gtc/type_ptr.hpp>

#include "render/passes/pass_env.hpp"

namespace candela {

void add_shadow_pass(FrameGraph& graph, const PassEnv& env, FrameTargets& targets) {
    graph.add_pass(
        "shadow_maps", [&](FrameGraph::Builder& b) { b.write(targets.shadow_maps); },
        [&env](FrameGraph::Context& ctx) {
            ShadowResources& sr = env.shadows;
            gl::PipelineState ps;
            ps.depth_test = true;
            ps.depth_func = GL_GREATER;
            ps.color_write = false;
            ps.polygon_offset_factor = -env.settings.shadow.slope_bias;
            ps.polygon_offset_units = -1.0f;
            ctx.state.apply(ps);
            ctx.state.viewport(0, 0, sr.resolution, sr.resolution);
            bind_scene_buffers(env);
            const GLuint program = env.programs.get("shadow").id();
            ctx.state.use_program(program);
            ctx.state.bind_vertex_array(env.scene.vertex_array().id());
            const auto& infos = env.scene.light_infos();
            for (size_t layer = 0; layer < sr.cpu.views.size(); ++layer) {
                ctx.state.bind_framebuffer(sr.layer_fbos[layer].id());
                const float clear_depth = 0.0f;  // reversed-Z far: lit
                glClearBufferfv(GL_DEPTH, 0, &clear_depth);
                if (sr.cpu.skip[layer]) continue;
                glProgramUniformMatrix4fv(program, 4, 1, GL_FALSE, glm::value_ptr(sr.cpu.views[layer].view_proj));
                const int own = infos[static_cast<size_t>(sr.cpu.light[layer])].own_draw;
                const auto& draws = env.scene.draws();
                for (size_t di = 0; di < draws.size(); ++di)
                    if (static_cast<int>(di) != own) draw_item(env, ctx, draws[di], false, GL_BACK, program);
            }
        });
}

}  // namespace candela
