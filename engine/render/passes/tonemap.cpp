// Display transform on the GPU into an RGBA8 target: what a window shows and what a .png holds.
// Planned only when the output is a display image; for .exr the HDR target is the output.
#include "gpu/bindings.h"
#include "render/passes/pass_env.hpp"

namespace candela {

void add_tonemap_pass(FrameGraph& graph, const PassEnv& env, FrameTargets& targets, const gl::Texture& display,
                      float exposure_ev) {
    graph.add_pass(
        "tonemap",
        [&](FrameGraph::Builder& b) {
            b.read(targets.hdr, SOURCE_UNIT);
            targets.display = graph.import_texture("display", display, {GL_RGBA8, env.width, env.height});
            b.write(targets.display);
        },
        [&env, &targets, exposure_ev](FrameGraph::Context& ctx) {
            ctx.state.apply(gl::PipelineState{.depth_test = false, .depth_write = false});
            ctx.state.bind_framebuffer(env.fbos.get({&ctx.texture(targets.display)}, nullptr));
            ctx.state.viewport(0, 0, env.width, env.height);
            ctx.state.use_program(env.programs.get("tonemap").id());
            glProgramUniform1f(env.programs.get("tonemap").id(), 0, exposure_ev);
            ctx.state.bind_vertex_array(env.empty_vao.id());
            glDrawArrays(GL_TRIANGLES, 0, 3);
            ++ctx.counters.draw_calls;
            ctx.counters.triangles += 1;
        });
}

}  // namespace candela
