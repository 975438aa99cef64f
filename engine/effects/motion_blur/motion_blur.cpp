#include "effects/motion_blur/motion_blur.hpp"

#include <algorithm>
#include <cstdio>

#include <glm/gtc/type_ptr.hpp>

#include "effects/motion_blur/motion_blur_data.h"
#include "effects/motion_blur/motion_blur_sweep.hpp"
#include "gpu/bindings.h"
#include "render/features.hpp"
#include "render/passes/pass_env.hpp"

namespace candela {
namespace {

// The passes, at Stage::post: "motion_velocity" (a copy of the HDR image, and the geometry
// redrawn with its positions at shutter open and close: half vectors and depth), "motion_tilemax"
// and "motion_neighbormax" (the dominant motion per tile and around it), "motion_gather" (the
// reconstruction, into the HDR target).
class MotionBlurRuntime final : public EffectRuntime {
    friend class MotionBlur;  // its plan hands each pass the member that adds it

public:
    void prepare(const FramePrep& p) override {
        const MotionBlurOptions& o = p.settings.get<MotionBlurOptions>();
        gpu::MotionBlurData d{};
        d.max_radius = static_cast<float>(o.max_radius);
        d.soft_z = o.soft_z;
        d.samples = o.samples;
        d.tile = std::max(o.max_radius, 1);
        tile_ = d.tile;
        if (!block_) block_ = gl::Buffer(sizeof d, nullptr, GL_DYNAMIC_STORAGE_BIT);
        block_.update(0, sizeof d, &d);
    }

private:
    struct Velocity {
        FrameGraph::ResourceId hdr = -1, color = -1, velocity = -1, depth = -1;
    };
    struct Data {
        FrameGraph::ResourceId in = -1, out = -1;
    };
    struct Gather {
        FrameGraph::ResourceId color = -1, velocity = -1, depth = -1, neighbor = -1, out = -1;
    };

    void bind_blocks(const PassEnv& env) const {
        glBindBufferBase(GL_UNIFORM_BUFFER, FRAME_BINDING, env.frame_ubo.id());
        glBindBufferBase(GL_UNIFORM_BUFFER, MOTION_BLUR_BINDING, block_.id());
    }

    void fullscreen(const PassEnv& env, FrameGraph::Context& ctx, GLuint fbo, int w, int h, GLuint program) const {
        bind_blocks(env);
        draw_fullscreen(env, ctx, fbo, w, h, program);
    }

    void add_velocity(FrameGraph& graph, const PassEnv& env, const FrameTargets& targets) {
        const GLuint program = env.programs.get("motion_velocity").id();
        const Velocity& data = graph.add_pass<Velocity>(
            "motion_velocity",
            [&](FrameGraph::Builder& b, Velocity& d) {
                d.hdr = b.read(targets.hdr);
                d.color = b.create("motion_color", {GL_RGBA32F, env.width, env.height});
                d.velocity = b.create("motion_velocity", {GL_RG16F, env.width, env.height});
                d.depth = b.create("motion_depth", {GL_DEPTH_COMPONENT32F, env.width, env.height});
            },
            [this, &env, program](const Velocity& d, FrameGraph::Context& ctx) {
                // The sharp image, read by the gather while it writes the HDR target.
                const gl::Texture& hdr = ctx.texture(d.hdr);
                glCopyImageSubData(hdr.id(), GL_TEXTURE_2D, 0, 0, 0, 0, ctx.texture(d.color).id(), GL_TEXTURE_2D, 0, 0, 0, 0,
                                   env.width, env.height, 1);
                bind_blocks(env);
                gl::PipelineState ps;
                ps.depth_test = true;  // reversed-Z: GL_GREATER, cleared to 0
                ctx.state.apply(ps);
                ctx.state.bind_framebuffer(env.fbos.get({&ctx.texture(d.velocity)}, &ctx.texture(d.depth)));
                ctx.state.viewport(0, 0, env.width, env.height);
                const float zero[4] = {0.0f, 0.0f, 0.0f, 0.0f};
                glClearBufferfv(GL_COLOR, 0, zero);
                glClearBufferfv(GL_DEPTH, 0, zero);
                if (!env.scene.has_motion()) return;  // nothing moves: no velocity, the gather copies
                ctx.state.use_program(program);
                ctx.state.bind_vertex_array(env.scene.motion_vertex_array().id());
                // The opaque and masked surfaces (masks drawn whole), both faces: the nearest one
                // is the one the image shows. Blended surfaces take the motion of what is behind.
                ctx.state.set_cull(false, GL_BACK);
                for (const GpuScene::Draw& draw : env.scene.draws()) {
                    if (draw.alpha_mode == AlphaMode::blend) continue;
                    glProgramUniformMatrix4fv(program, 0, 1, GL_FALSE, glm::value_ptr(draw.model));
                    glProgramUniformMatrix4fv(program, 1, 1, GL_FALSE, glm::value_ptr(draw.model_open));
                    glProgramUniformMatrix4fv(program, 2, 1, GL_FALSE, glm::value_ptr(draw.model_close));
                    glDrawElementsBaseVertex(GL_TRIANGLES, draw.index_count, GL_UNSIGNED_INT,
                                             reinterpret_cast<const void*>(draw.first_index * sizeof(std::uint32_t)), draw.base_vertex);
                    ++ctx.counters.draw_calls;
                    ctx.counters.triangles += static_cast<std::size_t>(draw.index_count / 3);
                }
            });
        color_ = data.color;
        velocity_ = data.velocity;
        depth_ = data.depth;
    }

    void add_tiles(FrameGraph& graph, const PassEnv& env, bool neighbor) {
        const char* name = neighbor ? "motion_neighbormax" : "motion_tilemax";
        const GLuint program = env.programs.get(name).id();
        const int k = tile_;
        const Data& data = graph.add_pass<Data>(
            name,
            [&](FrameGraph::Builder& b, Data& d) {
                d.in = b.read(neighbor ? tiles_ : velocity_, MOTION_BLUR_IN_UNIT);
                d.out = b.create(neighbor ? "motion_neighbormax" : "motion_tilemax",
                                 {GL_RG16F, (env.width + k - 1) / k, (env.height + k - 1) / k});
            },
            [this, &env, program](const Data& d, FrameGraph::Context& ctx) {
                const TextureDesc& desc = ctx.desc(d.out);
                fullscreen(env, ctx, env.fbos.get({&ctx.texture(d.out)}, nullptr), desc.width, desc.height, program);
            });
        tiles_ = data.out;
    }

    void add_gather(FrameGraph& graph, const PassEnv& env, FrameTargets& targets) {
        const GLuint program = env.programs.get("motion_gather").id();
        graph.add_pass<Gather>(
            "motion_gather",
            [&](FrameGraph::Builder& b, Gather& d) {
                d.color = b.read(color_, MOTION_BLUR_COLOR_UNIT);
                d.velocity = b.read(velocity_, MOTION_BLUR_COLOR_UNIT + 1);
                d.depth = b.read(depth_, MOTION_BLUR_COLOR_UNIT + 2);
                d.neighbor = b.read(tiles_, MOTION_BLUR_COLOR_UNIT + 3);
                d.out = b.write(targets.hdr);
            },
            [this, &env, program](const Gather& d, FrameGraph::Context& ctx) {
                fullscreen(env, ctx, env.fbos.get({&ctx.texture(d.out)}, nullptr), env.width, env.height, program);
            });
    }

    gl::Buffer block_;
    int tile_ = 20;
    FrameGraph::ResourceId color_ = -1, velocity_ = -1, depth_ = -1, tiles_ = -1;
};

int moving_draws_in_view(const Scene& scene, const GpuScene& gpu, const Camera& camera, float aspect) {
    if (!gpu.has_motion()) return 0;
    const glm::mat4 view_proj = projection_matrix(camera, aspect) * glm::inverse(camera.world);
    int count = 0;
    for (const GpuScene::Draw& d : gpu.draws()) {
        if (!d.moves) continue;
        const Node& node = scene.nodes[static_cast<size_t>(d.node)];
        const Bounds& local = scene.meshes[static_cast<size_t>(node.mesh)].primitives[static_cast<size_t>(d.primitive)].bounds;
        // Outside the view when all corners of the box at open, now and close lie beyond one clip plane.
        int outside[6] = {0, 0, 0, 0, 0, 0};
        int corners = 0;
        for (const glm::mat4* m : {&d.model_open, &d.model, &d.model_close})
            for (int c = 0; c < 8; ++c) {
                const glm::vec4 p = view_proj * (*m) * glm::vec4(c & 1 ? local.max.x : local.min.x, c & 2 ? local.max.y : local.min.y,
                                                                 c & 4 ? local.max.z : local.min.z, 1.0f);
                outside[0] += p.x < -p.w, outside[1] += p.x > p.w, outside[2] += p.y < -p.w, outside[3] += p.y > p.w;
                outside[4] += p.z > p.w, outside[5] += p.w <= 0.0f;  // reversed Z: z > w is in front of the near plane
                ++corners;
            }
        bool culled = false;
        for (int k = 0; k < 6; ++k) culled = culled || outside[k] == corners;
        count += !culled;
    }
    return count;
}

class MotionBlur final : public Effect {
public:
    const char* name() const override { return "motion_blur"; }
    std::any default_options() const override { return MotionBlurOptions{}; }
    std::vector<Knob> knobs() const override {
        return KnobRows<MotionBlurOptions>("motion_blur", [](RenderSettings& s) -> MotionBlurOptions& { return s.get<MotionBlurOptions>(); })
            .integer("max_radius", &MotionBlurOptions::max_radius, 1, 64,
                     "largest blur in pixels (half the motion over the shutter; longer motions are clamped) and the tile side")
            .integer("samples", &MotionBlurOptions::samples, 3, 255, "gather taps per pixel along the dominant motion (odd: the centre is the pixel)")
            .while_moving("5")
            .real("soft_z", &MotionBlurOptions::soft_z, 1e-4f, 10.0f,
                  "soft depth comparison: surfaces within this fraction of the view depth count as one")
            .rows;
    }
    // The draws that move while the shutter is open and whose bounds (at open, now or close) meet
    // the camera's view; 0 with the shutter closed or nothing uploaded.
    double view_amount(const ViewInput& in) const override {
        if (!(in.settings.camera.shutter > 0.0f) || !in.camera || !in.gpu) return 0.0;
        return moving_draws_in_view(in.scene, *in.gpu, with_lens(*in.camera, in.settings), in.aspect);
    }
    EffectDecision decide(const Features& f, const RenderSettings& s) const override {
        std::string reason;
        bool needed = false;
        const auto moving = static_cast<long>(f.view_amount(name()));
        if (!(s.camera.shutter > 0.0f)) reason = "camera.shutter is 0";
        else if (moving <= 0) reason = "nothing in view moves during the shutter";
        else {
            needed = true;
            reason = std::to_string(moving) + (moving == 1 ? " draw moves" : " draws move");
        }
        return decide_effect(name(), s.on(name()) && s.debug.view == DebugView::none, needed, reason, s.gating);
    }
    void plan(Stage stage, const Features& f, const RenderSettings& s, std::vector<PlannedPass>& out) const override {
        if (stage != Stage::post) return;
        const MotionBlurOptions& o = s.get<MotionBlurOptions>();
        char buf[160];
        std::snprintf(buf, sizeof buf, "%s during the shutter (%g of a frame at %g fps)", f.decision(name()).reason.substr(4).c_str(),
                      static_cast<double>(s.camera.shutter), static_cast<double>(s.camera.fps));
        using R = MotionBlurRuntime;
        out.push_back({"motion_velocity", buf, this, {"motion_velocity"}});
        out.back().work = runtime_pass<R>([](R& r, const PassSite& p) { r.add_velocity(p.graph, p.env, p.targets); });
        const std::string k = std::to_string(std::max(o.max_radius, 1));
        out.push_back({"motion_tilemax", "largest motion per " + k + "x" + k + " tile", this, {"motion_tilemax"}});
        out.back().work = runtime_pass<R>([](R& r, const PassSite& p) { r.add_tiles(p.graph, p.env, false); });
        out.push_back({"motion_neighbormax", "largest motion of the 3x3 tiles around", this, {"motion_neighbormax"}});
        out.back().work = runtime_pass<R>([](R& r, const PassSite& p) { r.add_tiles(p.graph, p.env, true); });
        out.push_back({"motion_gather", "reconstruction along the dominant motion, " + std::to_string(o.samples) + " taps", this, {"motion_gather"}});
        out.back().work = runtime_pass<R>([](R& r, const PassSite& p) { r.add_gather(p.graph, p.env, p.targets); });
    }
    std::vector<ProgramDesc> programs() const override {
        using S = ShaderStage;
        return {{"motion_velocity", {{S::vertex, "effects/motion_blur/velocity.vert"}, {S::fragment, "effects/motion_blur/velocity.frag"}}, {}},
                {"motion_tilemax", {{S::vertex, "post/fullscreen.vert"}, {S::fragment, "effects/motion_blur/tilemax.frag"}}, {}},
                {"motion_neighbormax", {{S::vertex, "post/fullscreen.vert"}, {S::fragment, "effects/motion_blur/tilemax.frag"}}, {"NEIGHBOR"}},
                {"motion_gather", {{S::vertex, "post/fullscreen.vert"}, {S::fragment, "effects/motion_blur/gather.frag"}}, {}}};
    }
    std::vector<GpuBlockInfo> gpu_blocks() const override {
        return {{"MotionBlurData", MOTION_BLUR_BINDING, sizeof(gpu::MotionBlurData), "motion_gather"}};
    }
    std::unique_ptr<EffectRuntime> create_runtime() const override { return std::make_unique<MotionBlurRuntime>(); }
    std::vector<AccuracySweep> accuracy_sweeps(bool quick) const override { return motion_blur_accuracy_sweeps(quick); }
};

}  // namespace

const Effect& motion_blur_effect() {
    static const MotionBlur effect;
    return effect;
}

}  // namespace candela
