#include "effects/transparency/transparency.hpp"

#include <algorithm>
#include <array>

#include "effects/transparency/transparency_sweep.hpp"
#include "gpu/bindings.h"
#include "render/features.hpp"
#include "render/passes/pass_env.hpp"

namespace candela {
namespace {

// The passes: "transparent" (sorted blending) or "transparent_peeling" (depth peeling), after the
// sky, over the opaque image and its depth.
class TransparencyRuntime final : public EffectRuntime {
    friend class Transparency;  // its plan hands each pass the member that adds it

public:
    void prepare(const FramePrep& p) override { options_ = p.settings.get<TransparencyOptions>(); }

private:
    // Alpha-blended geometry after everything opaque: back to front by the view depth of each
    // draw's bounds centre, SRC_ALPHA / ONE_MINUS_SRC_ALPHA, depth test on and depth write off;
    // double-sided meshes draw their back faces first.
    void add_sorted(FrameGraph& graph, const PassEnv& env, FrameTargets& targets) {
        graph.add_pass(
            "transparent",
            [&](FrameGraph::Builder& b) {
                b.read(targets.depth);
                read_lighting_inputs(b, env);
                b.write(targets.hdr);
            },
            [this, &env, &targets](FrameGraph::Context& ctx) {
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
                if (options_.sort == TransparencySort::triangle) {
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

    // Depth peeling (transparency.mode=peeling): the exact per-pixel order, layer by layer. Each
    // layer is the nearest blended fragment behind the previous layer and in front of the opaque
    // depth; it is composited front to back with UNDER into an accumulation buffer, which finally
    // goes OVER the opaque image. Exact up to transparency.layers layers per pixel; each layer
    // costs one draw of every blended object.
    void add_peeling(FrameGraph& graph, const PassEnv& env, FrameTargets& targets) {
        struct Data {
            std::array<FrameGraph::ResourceId, 4> ids{};  // color, depth a, depth b, accum
        };
        graph.add_pass<Data>(
            "transparent_peeling",
            [&](FrameGraph::Builder& b, Data& d) {
                b.read(targets.depth, OPAQUE_DEPTH_UNIT);
                read_lighting_inputs(b, env);
                b.write(targets.hdr);
                d.ids[0] = b.create("peel_color", {GL_RGBA16F, env.width, env.height});
                d.ids[1] = b.create("peel_depth_a", {GL_DEPTH_COMPONENT32F, env.width, env.height});
                d.ids[2] = b.create("peel_depth_b", {GL_DEPTH_COMPONENT32F, env.width, env.height});
                d.ids[3] = b.create("peel_accum", {GL_RGBA16F, env.width, env.height});
            },
            [this, &env, &targets](const Data& d, FrameGraph::Context& ctx) {
                const auto& [color, depth_a, depth_b, accum] = d.ids;
                const GLuint forward = env.programs.get("forward").id();
                const GLuint copy = env.programs.get("copy").id();
                auto fullscreen = [&](GLuint source) {
                    gl::bind_texture_unit(SOURCE_UNIT, source);
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
                for (int layer = 0; layer < options_.layers; ++layer) {
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
                    bind_effect_inputs(env, ctx);
                    gl::bind_texture_unit(PREVIOUS_LAYER_UNIT, ctx.texture(previous));
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
                // The pool may attach this depth texture next frame: leave no sampler on it (the
                // graph unbinds the opaque depth, a declared input).
                glBindTextureUnit(PREVIOUS_LAYER_UNIT, 0);
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

    TransparencyOptions options_;
};

class Transparency final : public Effect {
public:
    const char* name() const override { return "transparency"; }
    std::any default_options() const override { return TransparencyOptions{}; }
    std::vector<Knob> knobs() const override {
        return KnobRows<TransparencyOptions>("transparency",
                                             [](RenderSettings& s) -> TransparencyOptions& { return s.get<TransparencyOptions>(); })
            .choice("sort", &TransparencyOptions::sort, kTransparencySorts,
                    "back-to-front order of blended draws; triangle also orders each mesh's triangles (CPU, per frame)")
            .choice("mode", &TransparencyOptions::mode, kTransparencyModes,
                    "sorted blending, or depth peeling (exact per pixel up to transparency.layers layers)")
            .integer("layers", &TransparencyOptions::layers, 1, 64, "depth-peeling layers")
            .while_moving("4", "transparency.mode=peeling")
            .rows;
    }
    // Debug views show surface values of the nearest surface: blended ones count as opaque there,
    // as they do for the ray tracer's rays.
    EffectDecision decide(const Features& f, const RenderSettings& s) const override {
        return decide_effect(name(), s.on(name()) && s.debug.view == DebugView::none, f.scene.transparency.needed,
                             f.scene.transparency.reason, s.gating);
    }
    void plan(Stage stage, const Features& f, const RenderSettings& s, std::vector<PlannedPass>& out) const override {
        if (stage != Stage::blended) return;
        const TransparencyOptions& o = s.get<TransparencyOptions>();
        const std::string why = f.decision(name()).reason.substr(4);
        using R = TransparencyRuntime;
        if (o.mode == TransparencyMode::peeling) {
            out.push_back({"transparent_peeling", why + ", " + std::to_string(o.layers) + " depth-peeling layers", this, {"forward", "copy"}});
            out.back().work = runtime_pass<R>([](R& r, const PassSite& p) { r.add_peeling(p.graph, p.env, p.targets); });
        } else {
            out.push_back({"transparent", why, this, {"forward"}});
            out.back().work = runtime_pass<R>([](R& r, const PassSite& p) { r.add_sorted(p.graph, p.env, p.targets); });
        }
    }
    bool draws_blended_surfaces() const override { return true; }
    std::unique_ptr<EffectRuntime> create_runtime() const override { return std::make_unique<TransparencyRuntime>(); }
    std::vector<AccuracySweep> accuracy_sweeps(bool quick) const override { return transparency_accuracy_sweeps(quick); }
};

}  // namespace

const Effect& transparency_effect() {
    static const Transparency effect;
    return effect;
}

}  // namespace candela
