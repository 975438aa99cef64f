// Reflection probes: each probe's six cube faces rendered with the forward path from its
// position (opaque and masked geometry, then the sky), then GGX-prefiltered for rough
// reflections. Draws whose bounds contain the probe are left out (from inside they would only
// hide the room). Blended draws are left out too (no per-face sorting). Inside a probe, shading
// reads the static environment, not the probes (no feedback between probes), and no SSAO/RSM.
#include "render/passes/pass_env.hpp"

#include <algorithm>

namespace candela {

void add_env_probe_pass(FrameGraph& graph, const PassEnv& env, FrameTargets& targets) {
    graph.add_pass(
        "env_probe",
        [&](FrameGraph::Builder& b) {
            if (targets.shadow_maps >= 0) b.read(targets.shadow_maps);
            b.write(targets.probes);
        },
        [&env](FrameGraph::Context& ctx) {
            ProbeResources& pr = env.probes;
            bind_scene_buffers(env);
            const auto& draws = env.scene.draws();
            for (int k = 0; k < pr.cubes; ++k) {
                const ProbePlacement& placement = pr.placements[static_cast<size_t>(k)];
                std::vector<bool> skip(draws.size(), false);
                for (int i : placement.excluded_draws) skip[static_cast<size_t>(i)] = true;
                for (int face = 0; face < 6; ++face) {
                    const int layer = 6 * k + face;
                    glBindBufferRange(GL_UNIFORM_BUFFER, 0, pr.frames.id(), pr.frame_stride * layer, sizeof(FrameData));
                    gl::PipelineState ps;
                    ps.depth_test = true;
                    ps.depth_func = GL_GREATER;
                    ps.depth_write = true;
                    ctx.state.apply(ps);
                    ctx.state.bind_framebuffer(pr.face_fbos[static_cast<size_t>(layer)].id());
                    ctx.state.viewport(0, 0, pr.size, pr.size);
                    const float clear_color[4] = {0, 0, 0, 1};
                    glClearBufferfv(GL_COLOR, 0, clear_color);
                    const float clear_depth = 0.0f;
                    glClearBufferfv(GL_DEPTH, 0, &clear_depth);
                    ctx.state.use_program(env.programs.get("forward").id());
                    ctx.state.bind_vertex_array(env.scene.vertex_array().id());
                    for (size_t i = 0; i < draws.size(); ++i) {
                        const auto& d = draws[i];
                        if (skip[i] || d.alpha_mode == AlphaMode::blend) continue;
                        draw_item(env, ctx, d, !d.double_sided, GL_BACK);
                    }
                    if (pr.sky) {
                        gl::PipelineState sky;
                        sky.depth_test = true;
                        sky.depth_func = GL_GEQUAL;
                        sky.depth_write = false;
                        ctx.state.apply(sky);
                        ctx.state.use_program(env.programs.get("sky").id());
                        ctx.state.bind_vertex_array(env.empty_vao.id());
                        glDrawArrays(GL_TRIANGLES, 0, 3);
                        ++ctx.counters.draw_calls;
                        ++ctx.counters.triangles;
                    }
                }
            }
            glBindBufferBase(GL_UNIFORM_BUFFER, 0, env.frame_ubo.id());
            glTextureBarrier();
            glGenerateTextureMipmap(pr.capture.id());
            env.ibl.prefilter(pr.capture, pr.filtered, pr.size, pr.levels, pr.cubes, env.settings.probe.samples);
            ctx.counters.dispatches += pr.levels;
            // The prefilter changed programs and image bindings behind the state cache.
            ctx.state.reset();
            pr.valid = true;
        });
}

// Deferred path: transmissive surfaces, already in the G-buffer (for depth, SSAO and lighting of
// what is behind nothing), are shaded again with the forward program, which refracts through
// the probes; the depth test EQUAL keeps exactly the visible fragments.
void add_transmissive_pass(FrameGraph& graph, const PassEnv& env, FrameTargets& targets) {
    graph.add_pass(
        "transmissive",
        [&](FrameGraph::Builder& b) {
            b.read(targets.depth);
            read_lighting_inputs(b, env, targets);
            b.write(targets.hdr);
        },
        [&env, &targets](FrameGraph::Context& ctx) {
            gl::PipelineState ps;
            ps.depth_test = true;
            ps.depth_func = GL_EQUAL;
            ps.depth_write = false;
            begin_forward_shading(env, ctx, targets, ps);
            ctx.state.bind_vertex_array(env.scene.vertex_array().id());
            const Scene& scene = env.scene.scene();
            for (const auto& d : env.scene.draws())
                if (d.alpha_mode != AlphaMode::blend && scene.material(d.primitive_material).transmission > 0.0f)
                    draw_item(env, ctx, d, !d.double_sided, GL_BACK);
        });
}

}  // namespace candela
