// Forward shading of opaque and alpha-masked geometry into the linear HDR target.
#include <algorithm>

#include "core/error.hpp"
#include "render/effect.hpp"
#include "render/passes/pass_env.hpp"

namespace candela {

namespace {
// The lights that can reach each 16x16 tile, as bit sets in env.light_tiles (light_tiles.comp).
void cull_lights_per_tile(const PassEnv& env, FrameGraph::Context& ctx) {
    if (!env.light_tiles) throw Error(ExitCode::internal, "forward_opaque: tiled lights without the tiles' buffer");
    const int words = (env.frame.light_count + 31) / 32;
    const int tiles_x = (env.width + 15) / 16, tiles_y = (env.height + 15) / 16;
    const auto bytes = static_cast<GLsizeiptr>(std::max(1, tiles_x * tiles_y * words)) * 4;
    if (env.light_tiles->size() < bytes) *env.light_tiles = gl::Buffer(bytes, nullptr, 0);
    bind_scene_buffers(env);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, LIGHT_TILES_BINDING, env.light_tiles->id());
    ctx.state.use_program(env.programs.get("light_tiles").id());
    glDispatchCompute(static_cast<GLuint>(tiles_x), static_cast<GLuint>(tiles_y), 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    ++ctx.counters.dispatches;
}
}  // namespace

void add_forward_opaque_pass(FrameGraph& graph, const PassEnv& env, FrameTargets& targets, bool blend_as_opaque, bool tiled_lights) {
    // A prepass's depth serves (EQUAL) when it has the samples of the colour target: a
    // depth/normal prepass for screen-space effects stays single-sample under multisampling.
    const bool prepass = targets.depth >= 0 && graph.resources()[static_cast<size_t>(targets.depth)].desc.samples == targets.samples;
    const bool a2c = targets.samples > 1 && env.sampling.coverage;
    graph.add_pass(
        "forward_opaque",
        [&](FrameGraph::Builder& b) {
            if (targets.hdr < 0) targets.hdr = b.create("hdr_aa", {GL_RGBA32F, env.width, env.height, targets.samples});
            else b.write(targets.hdr);
            read_lighting_inputs(b, env);
            if (prepass) b.read(targets.depth);
            else targets.depth = b.create(targets.samples > 1 ? "depth_aa" : "depth",
                                          {GL_DEPTH_COMPONENT32F, env.width, env.height, targets.samples});
        },
        [&env, &targets, prepass, blend_as_opaque, a2c, tiled_lights](FrameGraph::Context& ctx) {
            if (tiled_lights) cull_lights_per_tile(env, ctx);
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
            // Specialised to this frame's features (pass_env.hpp): opaque geometry never peels.
            const GLuint forward = env.programs.get(forward_program_name(env, false, tiled_lights)).id();
            ctx.state.use_program(forward);
            ctx.state.bind_vertex_array(env.scene.vertex_array().id());
            // MASK materials with multisampling: alpha to coverage (forward.frag, u_alpha_to_coverage).
            if (a2c) {
                glEnable(GL_SAMPLE_ALPHA_TO_COVERAGE);
                glEnable(GL_SAMPLE_ALPHA_TO_ONE);  // the stored alpha stays 1 (opaque)
                glProgramUniform1i(forward, 9, 1);
            }
            for (const auto& d : env.scene.draws()) {
                // When no planned effect draws them (Effect::draws_blended_surfaces), blended
                // materials are drawn as opaque ones (after a prepass that skipped them they
                // would fail the EQUAL test, so skip).
                if (d.alpha_mode == AlphaMode::blend && (!blend_as_opaque || (prepass && !targets.prepass_has_blend))) continue;
                draw_item(env, ctx, d, !d.double_sided, GL_BACK, forward);
            }
            if (a2c) {
                glDisable(GL_SAMPLE_ALPHA_TO_COVERAGE);
                glDisable(GL_SAMPLE_ALPHA_TO_ONE);
                glProgramUniform1i(forward, 9, 0);
            }
        });
}

}  // namespace candela
