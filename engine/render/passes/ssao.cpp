// SSAO (shaders/ssao/): on the forward path a depth + normal prepass first (the shading pass then
// runs with depth test EQUAL); on the deferred path the G-buffer's normals. Then the AO buffer
// at full or half resolution, and a separable depth-aware blur. The lighting multiplies only the
// ambient/environment term by it.
#include <memory>

#include "render/passes/pass_env.hpp"

namespace candela {

void add_depth_normal_prepass(FrameGraph& graph, const PassEnv& env, ForwardTargets& targets, bool blend_as_opaque) {
    targets.prepass_has_blend = blend_as_opaque;
    graph.add_pass(
        "depth_normal_prepass",
        [&](FrameGraph::Builder& b) {
            targets.depth = b.create("depth", {GL_DEPTH_COMPONENT32F, env.width, env.height});
            targets.normals = b.create("normals", {GL_RG16F, env.width, env.height});
        },
        [&env, &targets, blend_as_opaque](FrameGraph::Context& ctx) {
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
            const GLuint program = env.programs.ssao_normals.id();
            ctx.state.use_program(program);
            ctx.state.bind_vertex_array(env.scene.vertex_array().id());
            for (const auto& d : env.scene.draws())
                if (d.alpha_mode != AlphaMode::blend || blend_as_opaque) draw_item(env, ctx, d, !d.double_sided, GL_BACK, program);
        });
}

namespace {
int ao_downscale(const PassEnv& env) { return env.settings.ssao_knobs.resolution == "half" ? 2 : 1; }

void fullscreen(const PassEnv& env, FrameGraph::Context& ctx, GLuint fbo, int w, int h, GLuint program) {
    gl::PipelineState ps;
    ctx.state.apply(ps);
    ctx.state.bind_framebuffer(fbo);
    ctx.state.viewport(0, 0, w, h);
    ctx.state.use_program(program);
    ctx.state.bind_vertex_array(env.empty_vao.id());
    glDrawArrays(GL_TRIANGLES, 0, 3);
    ++ctx.counters.draw_calls;
    ctx.counters.triangles += 1;
}
}  // namespace

void add_ssao_pass(FrameGraph& graph, const PassEnv& env, ForwardTargets& targets) {
    graph.add_pass(
        "ssao",
        [&](FrameGraph::Builder& b) {
            b.read(targets.depth);
            b.read(targets.normals);
            const int f = ao_downscale(env);
            targets.ssao = b.create("ssao", {GL_RG16F, (env.width + f - 1) / f, (env.height + f - 1) / f});
        },
        [&env, &targets](FrameGraph::Context& ctx) {
            glBindBufferBase(GL_UNIFORM_BUFFER, 0, env.frame_ubo.id());
            glBindTextureUnit(0, ctx.texture(targets.depth).id());
            glBindSampler(0, 0);
            glBindTextureUnit(1, ctx.texture(targets.normals).id());
            glBindSampler(1, 0);
            glBindTextureUnit(2, env.ssao_noise.id());
            glBindSampler(2, 0);
            const TextureDesc& d = ctx.desc(targets.ssao);
            fullscreen(env, ctx, env.fbos.get({&ctx.texture(targets.ssao)}, nullptr), d.width, d.height, env.programs.ssao.id());
        });
}

void add_ssao_blur_pass(FrameGraph& graph, const PassEnv& env, ForwardTargets& targets, int axis) {
    // Input and output of this axis; filled by the setup, which runs at once.
    auto io = std::make_shared<std::pair<FrameGraph::ResourceId, FrameGraph::ResourceId>>(-1, -1);
    const char* name = axis == 0 ? "ssao_blur_x" : "ssao_blur_y";
    graph.add_pass(
        name,
        [&, io, name](FrameGraph::Builder& b) {
            io->first = b.read(targets.ssao);
            io->second = b.create(name, graph.resources()[static_cast<size_t>(io->first)].desc);
            targets.ssao = io->second;
        },
        [&env, &targets, io, axis](FrameGraph::Context& ctx) {
            glBindBufferBase(GL_UNIFORM_BUFFER, 0, env.frame_ubo.id());
            glBindTextureUnit(0, ctx.texture(io->first).id());
            glBindSampler(0, 0);
            const GLuint program = env.programs.ssao_blur.id();
            glProgramUniform2i(program, 0, axis == 0 ? 1 : 0, axis == 0 ? 0 : 1);
            const TextureDesc& d = ctx.desc(io->second);
            fullscreen(env, ctx, env.fbos.get({&ctx.texture(io->second)}, nullptr), d.width, d.height, program);
        });
}

}  // namespace candela
