// Reflective shadow maps and their gather (shaders/rsm/): the RSM pass renders, for each RSM
// light, its shadow views again at rsm.resolution with position, normal and reflected flux; the
// gather pass sums rsm.samples texels per pixel into one-bounce irradiance at rsm.gather
// resolution, which the lighting upsamples bilinearly and adds through the Lambert term.
#include <algorithm>

#include <glm/gtc/type_ptr.hpp>

#include "render/passes/pass_env.hpp"

namespace candela {

void add_rsm_pass(FrameGraph& graph, const PassEnv& env, FrameTargets& targets) {
    graph.add_pass(
        "rsm", [&](FrameGraph::Builder& b) { b.write(targets.rsm); },
        [&env](FrameGraph::Context& ctx) {
            RsmResources& r = env.rsm;
            gl::PipelineState ps;
            ps.depth_test = true;
            ctx.state.apply(ps);
            ctx.state.viewport(0, 0, r.resolution, r.resolution);
            bind_scene_buffers(env);
            const GLuint program = env.programs.get("rsm").id();
            ctx.state.use_program(program);
            ctx.state.bind_vertex_array(env.scene.vertex_array().id());
            for (size_t layer = 0; layer < r.views.size(); ++layer) {
                ctx.state.bind_framebuffer(r.layer_fbos[layer].id());
                const float zero[4] = {0, 0, 0, 0};
                for (int i = 0; i < 3; ++i) glClearBufferfv(GL_COLOR, i, zero);
                const float clear_depth = 0.0f;
                glClearBufferfv(GL_DEPTH, 0, &clear_depth);
                const glm::mat4& vp = r.views[layer].view_proj;
                glProgramUniformMatrix4fv(program, 4, 1, GL_FALSE, glm::value_ptr(vp));
                glProgramUniform1i(program, 5, static_cast<int>(r.views[layer].params.x));
                glProgramUniform4fv(program, 6, 1, glm::value_ptr(r.kind_texel[layer]));
                // Perspective: clip w = distance along the view axis, so row 3 of the matrix is it.
                const glm::vec3 axis(vp[0][3], vp[1][3], vp[2][3]);
                glProgramUniform3fv(program, 7, 1, glm::value_ptr(axis));
                for (const auto& d : env.scene.draws()) draw_item(env, ctx, d, false, GL_BACK, program);
            }
        });
}

void add_rsm_gather_pass(FrameGraph& graph, const PassEnv& env, FrameTargets& targets) {
    graph.add_pass(
        "rsm_indirect",
        [&](FrameGraph::Builder& b) {
            b.read(targets.depth);
            b.read(targets.normals);
            b.read(targets.rsm);
            const std::string& g = env.settings.rsm_knobs.gather;
            const int f = g == "quarter" ? 4 : g == "half" ? 2 : 1;
            targets.rsm_indirect = b.create("rsm_indirect", {GL_RGBA16F, (env.width + f - 1) / f, (env.height + f - 1) / f});
        },
        [&env, &targets](FrameGraph::Context& ctx) {
            RsmResources& r = env.rsm;
            bind_scene_buffers(env);
            glBindTextureUnit(0, ctx.texture(targets.depth).id());
            glBindSampler(0, 0);
            glBindTextureUnit(1, ctx.texture(targets.normals).id());
            glBindSampler(1, 0);
            const gl::Texture* maps[3] = {&r.position, &r.normal, &r.flux};
            for (int i = 0; i < 3; ++i) {
                glBindTextureUnit(static_cast<GLuint>(2 + i), maps[i]->id());
                glBindSampler(static_cast<GLuint>(2 + i), env.shadows.raw.id());  // nearest: never blend two surfaces
            }
            glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, r.views_buffer.id());
            const GLuint program = env.programs.get("rsm_gather").id();
            const std::string& g = env.settings.rsm_knobs.gather;
            const int f = g == "quarter" ? 4 : g == "half" ? 2 : 1;
            glProgramUniform1i(program, 0, static_cast<int>(r.light_first.size()));
            glProgramUniform4i(program, 1, r.resolution, env.settings.rsm_knobs.samples, f, 0);
            glProgramUniform1f(program, 2, env.settings.rsm_knobs.radius);
            std::vector<int> first(8, 0);
            std::copy_n(r.light_first.begin(), std::min<size_t>(8, r.light_first.size()), first.begin());
            glProgramUniform1iv(program, 3, 8, first.data());
            gl::PipelineState ps;
            ctx.state.apply(ps);
            const TextureDesc& d = ctx.desc(targets.rsm_indirect);
            ctx.state.bind_framebuffer(env.fbos.get({&ctx.texture(targets.rsm_indirect)}, nullptr));
            ctx.state.viewport(0, 0, d.width, d.height);
            ctx.state.use_program(program);
            ctx.state.bind_vertex_array(env.empty_vao.id());
            glDrawArrays(GL_TRIANGLES, 0, 3);
            ++ctx.counters.draw_calls;
            ctx.counters.triangles += 1;
        });
}

}  // namespace candela
