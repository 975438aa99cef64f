// Alpha-blended geometry after everything opaque: back to front by the view depth of each
// draw's bounds centre, SRC_ALPHA / ONE_MINUS_SRC_ALPHA, depth test on and depth write off;
// double-sided meshes draw their back faces first.
#include <algorithm>
#include <array>
#include <memory>

#include "render/passes/pass_env.hpp"

namespace candela {

void add_transparent_pass(FrameGraph& graph, const PassEnv& env, FrameTargets& targets) {
    graph.add_pass(
        "transparent",
        [&](FrameGraph::Builder& b) {
            b.read(targets.depth);
            read_lighting_inputs(b, env, targets);
            b.write(targets.hdr);
        },
        [&env, &targets](FrameGraph::Context& ctx) {
            std::vector<const GpuScene::Draw*> blended;
            for (const auto& d : env.scene.draws())
                if (d.alpha_mode == AlphaMode::blend) blended.push_back(&d);
            auto view_depth = [&](const GpuScene::Draw* d) {
                return (env.frame.view * glm::vec4(d->world_bounds.center(), 1.0f)).z;  // more negative = farther
            };
            std::stable_sort(blended.begin(), blended.end(), [&](auto* a, auto* b) { return view_depth(a) < view_depth(b); });
            gl::PipelineState ps;
            ps.depth_test = true;
            ps.depth_write = false;
            ps.blend = true;
            ps.blend_src_rgb = GL_SRC_ALPHA;
            ps.blend_dst_rgb = GL_ONE_MINUS_SRC_ALPHA;
            ps.blend_src_alpha = GL_ZERO;
            ps.blend_dst_alpha = GL_ONE;
            begin_forward_shading(env, ctx, targets, ps);
            std::vector<GpuScene::Draw> draws;
            for (const auto* d : blended) draws.push_back(*d);
            if (env.settings.transparency_knobs.sort == "triangle") {
                // Each mesh's triangles back to front by the view depth of their centroids, into
                // the per-frame index buffer (CPU: a few thousand blended triangles at most here).
                std::vector<std::uint32_t> indices;
                const Scene& scene = env.scene.scene();
                for (GpuScene::Draw& d : draws) {
                    const Node& node = scene.nodes[static_cast<size_t>(d.node)];
                    const Primitive& p = scene.meshes[static_cast<size_t>(node.mesh)].primitives[static_cast<size_t>(d.primitive)];
                    const glm::mat4 model_view = env.frame.view * d.model;
                    std::vector<std::pair<float, std::uint32_t>> order;
                    for (std::uint32_t t = 0; t < static_cast<std::uint32_t>(p.indices.size() / 3); ++t) {
                        glm::vec3 c(0.0f);
                        for (int k = 0; k < 3; ++k) c += p.vertices[p.indices[t * 3 + static_cast<std::uint32_t>(k)]].position;
                        order.emplace_back((model_view * glm::vec4(c / 3.0f, 1.0f)).z, t);
                    }
                    std::stable_sort(order.begin(), order.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
                    d.first_index = indices.size();
                    for (const auto& [z, t] : order)
                        for (int k = 0; k < 3; ++k) indices.push_back(p.indices[t * 3 + static_cast<std::uint32_t>(k)]);
                }
                env.scene.upload_sorted_indices(indices);
                ctx.state.bind_vertex_array(env.scene.sorted_vertex_array().id());
                // Sorted triangles are drawn in their order whichever way they face.
                for (const auto& d : draws) draw_item(env, ctx, d, !d.double_sided, GL_BACK);
            } else {
                ctx.state.bind_vertex_array(env.scene.vertex_array().id());
                for (const auto& d : draws) {
                    if (d.double_sided) draw_item(env, ctx, d, true, GL_FRONT);
                    draw_item(env, ctx, d, true, GL_BACK);
                }
            }
        });
}

}  // namespace candela

namespace candela {

// Depth peeling (transparency.mode=peeling): the exact per-pixel order, layer by layer. Each
// layer is the nearest blended fragment behind the previous layer and in front of the opaque
// depth; it is composited front to back with UNDER into an accumulation buffer, which finally
// goes OVER the opaque image. Exact up to transparency.layers layers per pixel; each layer costs
// one draw of every blended object.
void add_peeling_pass(FrameGraph& graph, const PassEnv& env, FrameTargets& targets) {
    auto ids = std::make_shared<std::array<FrameGraph::ResourceId, 4>>();  // color, depth a, depth b, accum
    graph.add_pass(
        "transparent_peeling",
        [&, ids](FrameGraph::Builder& b) {
            b.read(targets.depth);
            read_lighting_inputs(b, env, targets);
            b.write(targets.hdr);
            (*ids)[0] = b.create("peel_color", {GL_RGBA16F, env.width, env.height});
            (*ids)[1] = b.create("peel_depth_a", {GL_DEPTH_COMPONENT32F, env.width, env.height});
            (*ids)[2] = b.create("peel_depth_b", {GL_DEPTH_COMPONENT32F, env.width, env.height});
            (*ids)[3] = b.create("peel_accum", {GL_RGBA16F, env.width, env.height});
        },
        [&env, &targets, ids](FrameGraph::Context& ctx) {
            const auto& [color, depth_a, depth_b, accum] = *ids;
            const GLuint forward = env.programs.get("forward").id();
            const GLuint copy = env.programs.get("copy").id();
            auto fullscreen = [&](GLuint source) {
                glBindTextureUnit(0, source);
                glBindSampler(0, 0);
                ctx.state.use_program(copy);
                ctx.state.bind_vertex_array(env.empty_vao.id());
                glDrawArrays(GL_TRIANGLES, 0, 3);
                ++ctx.counters.draw_calls;
                ctx.counters.triangles += 1;
            };
            ctx.state.viewport(0, 0, env.width, env.height);
            ctx.state.bind_framebuffer(env.fbos.get({&ctx.texture(accum)}, nullptr));
            const float zero[4] = {0, 0, 0, 0};
            glClearBufferfv(GL_COLOR, 0, zero);
            glBindTextureUnit(11, ctx.texture(targets.depth).id());
            glBindSampler(11, 0);
            for (int layer = 0; layer < env.settings.transparency_knobs.layers; ++layer) {
                const FrameGraph::ResourceId depth = layer % 2 == 0 ? depth_a : depth_b;
                const FrameGraph::ResourceId previous = layer % 2 == 0 ? depth_b : depth_a;
                gl::PipelineState ps;
                ps.depth_test = true;
                ctx.state.apply(ps);
                ctx.state.bind_framebuffer(env.fbos.get({&ctx.texture(color)}, &ctx.texture(depth)));
                glClearBufferfv(GL_COLOR, 0, zero);
                const float clear_depth = 0.0f;
                glClearBufferfv(GL_DEPTH, 0, &clear_depth);
                bind_scene_buffers(env);
                bind_ssao(env, &ctx, targets);
                glBindTextureUnit(12, ctx.texture(previous).id());
                glBindSampler(12, 0);
                ctx.state.use_program(forward);
                glProgramUniform1i(forward, 8, layer == 0 ? 1 : 2);
                ctx.state.bind_vertex_array(env.scene.vertex_array().id());
                for (const auto& d : env.scene.draws())
                    if (d.alpha_mode == AlphaMode::blend) draw_item(env, ctx, d, !d.double_sided, GL_BACK);
                // accum += (1 - accum.a) * layer (premultiplied): front-to-back UNDER.
                gl::PipelineState under;
                under.blend = true;
                under.blend_src_rgb = under.blend_src_alpha = GL_ONE_MINUS_DST_ALPHA;
                under.blend_dst_rgb = under.blend_dst_alpha = GL_ONE;
                ctx.state.apply(under);
                ctx.state.bind_framebuffer(env.fbos.get({&ctx.texture(accum)}, nullptr));
                fullscreen(ctx.texture(color).id());
            }
            glProgramUniform1i(forward, 8, 0);
            // The pool may attach these depth textures next frame: leave no sampler on them.
            glBindTextureUnit(11, 0);
            glBindTextureUnit(12, 0);
            // hdr = accum + (1 - accum.a) * hdr: OVER the opaque image; hdr's alpha stays.
            gl::PipelineState over;
            over.blend = true;
            over.blend_src_rgb = GL_ONE;
            over.blend_dst_rgb = GL_ONE_MINUS_SRC_ALPHA;
            over.blend_src_alpha = GL_ZERO;
            over.blend_dst_alpha = GL_ONE;
            ctx.state.apply(over);
            ctx.state.bind_framebuffer(env.fbos.get({&ctx.texture(targets.hdr)}, nullptr));
            fullscreen(ctx.texture(accum).id());
        });
}

}  // namespace candela
