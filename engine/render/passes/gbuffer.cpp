// Deferred path, first pass: the surface of every opaque and masked fragment into the G-buffer
// (layout: shaders/lighting/gbuffer.glsl) and its emission into the light buffer.
// Multisampled (targets.samples > 1, FrameSampling) the G-buffer, its depth and the light buffer are
// multisampled; "gbuffer_resolve" then copies sample 0's depth and normal into single-sample
// textures for the screen-space effects (Stage::screen), and the lighting pass shades once per
// pixel, or at the edge pixels once per surface their samples show (shaders/deferred/light.comp).
#include "render/effect.hpp"
#include "gpu/bindings.h"
#include "render/passes/pass_env.hpp"

namespace candela {

void add_gbuffer_pass(FrameGraph& graph, const PassEnv& env, FrameTargets& targets, bool blend_as_opaque) {
    // Its own ids: the resolve replaces targets.depth and targets.normals after it.
    struct Data {
        FrameGraph::ResourceId hdr = -1, depth = -1, gbuffer[3] = {-1, -1, -1};
    };
    const int n = targets.samples;
    // MASK materials with multisampling: their coverage from alpha (gbuffer.frag).
    const bool a2c = n > 1 && env.sampling.coverage;
    graph.add_pass<Data>(
        "gbuffer",
        [&, n](FrameGraph::Builder& b, Data& d) {
            // Targets of their own (FrameSampling::resolved): the first pass that draws colour
            // makes the (multisampled) light buffer.
            if (targets.hdr < 0) targets.hdr = b.create("hdr_aa", {GL_RGBA32F, env.width, env.height, n});
            else b.write(targets.hdr);
            const char* suffix = n > 1 ? "_aa" : "";
            auto name = [suffix](const char* base) { return std::string(base) + suffix; };
            targets.depth = b.create(name("depth"), {GL_DEPTH_COMPONENT32F, env.width, env.height, n});
            targets.gbuffer[0] = b.create(name("gbuffer_base_occlusion"), {GL_RGBA8, env.width, env.height, n});
            targets.gbuffer[1] = b.create(name("gbuffer_normal_roughness_metallic"), {GL_RGBA16F, env.width, env.height, n});
            targets.gbuffer[2] = b.create(name("gbuffer_f0_f90"), {GL_RGBA16F, env.width, env.height, n});
            targets.normals = targets.gbuffer[1];
            targets.gbuffer_depth = targets.depth;
            d.hdr = targets.hdr;
            d.depth = targets.depth;
            for (int i = 0; i < 3; ++i) d.gbuffer[i] = targets.gbuffer[i];
        },
        [&env, blend_as_opaque, a2c](const Data& targets, FrameGraph::Context& ctx) {
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
            const GLuint program = env.programs.get(material_layers_on(env) ? "gbuffer#MATERIAL_LAYERS" : "gbuffer").id();
            ctx.state.use_program(program);
            ctx.state.bind_vertex_array(env.scene.vertex_array().id());
            if (a2c) glProgramUniform1i(program, 9, 1);
            for (const auto& d : env.scene.draws()) {
                if (d.alpha_mode == AlphaMode::blend && !blend_as_opaque) continue;
                draw_item(env, ctx, d, !d.double_sided, GL_BACK, program);
            }
            if (a2c) glProgramUniform1i(program, 9, 0);
        });
}

// Multisampled G-buffer only: sample 0's depth and octahedral normal into single-sample textures,
// which become targets.depth and targets.normals for Stage::screen (SSAO, RSM read them as
// sampler2D). Sample 0 rather than a mean: depth and normal then belong to one surface, as a
// single-sample G-buffer's would. deferred_lighting puts the multisampled depth back into
// targets.depth for the passes that draw after it (transmissive, sky, transparent, the resolve).
void add_gbuffer_resolve_pass(FrameGraph& graph, const PassEnv& env, FrameTargets& targets) {
    struct Data {
        FrameGraph::ResourceId depth_ms = -1, normal_ms = -1, depth = -1, normals = -1;
    };
    graph.add_pass<Data>(
        "gbuffer_resolve",
        [&](FrameGraph::Builder& b, Data& d) {
            d.depth_ms = b.read(targets.gbuffer_depth, RESOLVE_DEPTH_UNIT);
            d.normal_ms = b.read(targets.gbuffer[1], RESOLVE_NORMAL_UNIT);
            d.depth = targets.depth = b.create("depth", {GL_DEPTH_COMPONENT32F, env.width, env.height});
            d.normals = targets.normals = b.create("normals", {GL_RG16F, env.width, env.height});
        },
        [&env](const Data& d, FrameGraph::Context& ctx) {
            gl::PipelineState ps;
            ps.depth_test = true;
            ps.depth_func = GL_ALWAYS;
            ps.depth_write = true;
            ctx.state.apply(ps);
            ctx.state.bind_framebuffer(env.fbos.get({&ctx.texture(d.normals)}, &ctx.texture(d.depth)));
            ctx.state.viewport(0, 0, env.width, env.height);
            ctx.state.use_program(env.programs.get("gbuffer_resolve").id());
            ctx.state.bind_vertex_array(env.empty_vao.id());
            glDrawArrays(GL_TRIANGLES, 0, 3);
            ++ctx.counters.draw_calls;
            ctx.counters.triangles += 1;
            // The pool may attach these textures to framebuffers next: leave no unit on them.
            glBindTextureUnit(RESOLVE_DEPTH_UNIT, 0);
            glBindTextureUnit(RESOLVE_NORMAL_UNIT, 0);
        });
}

}  // namespace candela
