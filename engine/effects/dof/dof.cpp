#include "effects/dof/dof.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "effects/dof/dof_data.h"
#include "effects/dof/dof_sweep.hpp"
#include "gpu/bindings.h"
#include "render/features.hpp"
#include "render/passes/pass_env.hpp"
#include "scene/scene.hpp"

namespace candela {
namespace {

constexpr int kTile = 16;  // pixels per side of a near-field tile

// The passes, at Stage::post: "dof_coc" (colour + signed CoC), "dof_tiles" and "dof_dilate" (the
// near field's reach per tile), "dof_gather" (both fields, composited into the HDR target).
class DofRuntime final : public EffectRuntime {
    friend class Dof;  // its plan hands each pass the member that adds it

public:
    void prepare(const FramePrep& p) override {
        const DofOptions& o = p.settings.get<DofOptions>();
        gpu::DofData d{};
        const Camera& cam = p.camera;  // the lens-applied camera
        const float focus = std::max(focus_distance_or_auto(cam, p.scene_bounds), 1e-6f);
        const float tan_half = std::tan(0.5f * cam.yfov);
        // The CoC radius at infinite depth, in pixels: the thin lens's blur circle on the focus
        // plane (diameter 2 A |d - F| / d) over the plane's height per pixel (2 F tan(yfov/2) / H).
        float scale = has_thin_lens(cam) && tan_half > 0.0f ? cam.aperture * static_cast<float>(p.height) / (2.0f * focus * tan_half) : 0.0f;
        if (!std::isfinite(scale)) scale = 0.0f;
        d.coc_scale = scale;
        d.focus = focus;
        d.max_radius = 0.5f * o.max_coc;
        d.samples = o.samples;
        d.tile = kTile;
        d.tile_reach = static_cast<int>(std::ceil(d.max_radius / static_cast<float>(kTile)));
        if (!block_) block_ = gl::Buffer(sizeof d, nullptr, GL_DYNAMIC_STORAGE_BIT);
        block_.update(0, sizeof d, &d);
    }

private:
    struct Data {
        FrameGraph::ResourceId in = -1, in2 = -1, out = -1;
    };

    void fullscreen(const PassEnv& env, FrameGraph::Context& ctx, GLuint fbo, int w, int h, GLuint program) const {
        glBindBufferBase(GL_UNIFORM_BUFFER, FRAME_BINDING, env.frame_ubo.id());
        glBindBufferBase(GL_UNIFORM_BUFFER, DOF_BINDING, block_.id());
        draw_fullscreen(env, ctx, fbo, w, h, program);
    }

    void add_coc(FrameGraph& graph, const PassEnv& env, const FrameTargets& targets) {
        const GLuint program = env.programs.get("dof_coc").id();
        const Data& data = graph.add_pass<Data>(
            "dof_coc",
            [&](FrameGraph::Builder& b, Data& d) {
                d.in = b.read(targets.hdr, DOF_IN_UNIT);
                d.in2 = b.read(targets.depth, DOF_IN2_UNIT);
                d.out = b.create("dof_color", {GL_RGBA32F, env.width, env.height});
            },
            [this, &env, program](const Data& d, FrameGraph::Context& ctx) {
                fullscreen(env, ctx, env.fbos.get({&ctx.texture(d.out)}, nullptr), env.width, env.height, program);
            });
        color_ = data.out;
    }

    void add_tiles(FrameGraph& graph, const PassEnv& env, bool dilate) {
        const char* name = dilate ? "dof_dilate" : "dof_tiles";
        const GLuint program = env.programs.get(name).id();
        const Data& data = graph.add_pass<Data>(
            name,
            [&](FrameGraph::Builder& b, Data& d) {
                d.in = b.read(dilate ? tiles_ : color_, DOF_IN_UNIT);
                d.out = b.create(dilate ? "dof_near_reach" : "dof_near_tiles",
                                 {GL_R32F, (env.width + kTile - 1) / kTile, (env.height + kTile - 1) / kTile});
            },
            [this, &env, program](const Data& d, FrameGraph::Context& ctx) {
                const TextureDesc& desc = ctx.desc(d.out);
                fullscreen(env, ctx, env.fbos.get({&ctx.texture(d.out)}, nullptr), desc.width, desc.height, program);
            });
        tiles_ = data.out;
    }

    void add_gather(FrameGraph& graph, const PassEnv& env, FrameTargets& targets) {
        const GLuint program = env.programs.get("dof_gather").id();
        graph.add_pass<Data>(
            "dof_gather",
            [&](FrameGraph::Builder& b, Data& d) {
                d.in = b.read(color_, DOF_IN_UNIT);
                d.in2 = b.read(tiles_, DOF_IN2_UNIT);
                d.out = b.write(targets.hdr);
            },
            [this, &env, program](const Data& d, FrameGraph::Context& ctx) {
                fullscreen(env, ctx, env.fbos.get({&ctx.texture(d.out)}, nullptr), env.width, env.height, program);
            });
    }

    gl::Buffer block_;
    FrameGraph::ResourceId color_ = -1, tiles_ = -1;  // this frame's colour + CoC, and near tiles
};

std::string lens_reason(float aperture) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "camera aperture %g", static_cast<double>(aperture));
    return buf;
}

class Dof final : public Effect {
public:
    const char* name() const override { return "dof"; }
    std::any default_options() const override { return DofOptions{}; }
    std::vector<Knob> knobs() const override {
        return KnobRows<DofOptions>("dof", [](RenderSettings& s) -> DofOptions& { return s.get<DofOptions>(); })
            .real("max_coc", &DofOptions::max_coc, 2.0f, 256.0f,
                  "largest circle of confusion (diameter, pixels); larger blur circles are clamped to it")
            .integer("samples", &DofOptions::samples, 4, 256, "gather samples per pixel for each of the near and far fields")
            .while_moving("8")
            .rows;
    }
    // The aperture of the lens the frames use (the settings' over the camera's own; without a
    // camera, the settings' alone): a pinhole (0) needs no depth of field.
    double view_amount(const ViewInput& in) const override {
        return in.camera ? with_lens(*in.camera, in.settings).aperture : std::max(0.0f, in.settings.camera.aperture);
    }
    EffectDecision decide(const Features& f, const RenderSettings& s) const override {
        const auto aperture = static_cast<float>(f.view_amount(name()));
        const bool needed = aperture > 0.0f;
        // decide_effect prefixes "on: " / "off: ".
        const std::string reason = needed ? lens_reason(aperture) : "pinhole camera (aperture 0)";
        return decide_effect(name(), s.on(name()) && s.debug.view == DebugView::none, needed, reason, s.gating);
    }
    void plan(Stage stage, const Features& f, const RenderSettings& s, std::vector<PlannedPass>& out) const override {
        if (stage != Stage::post) return;
        const DofOptions& o = s.get<DofOptions>();
        char buf[128];
        std::snprintf(buf, sizeof buf, "%s, max CoC %g px", f.decision(name()).reason.substr(4).c_str(), static_cast<double>(o.max_coc));
        using R = DofRuntime;
        out.push_back({"dof_coc", buf, this, {"dof_coc"}});
        out.back().work = runtime_pass<R>([](R& r, const PassSite& p) { r.add_coc(p.graph, p.env, p.targets); });
        out.push_back({"dof_tiles", "near-field reach per 16x16 tile", this, {"dof_tiles"}});
        out.back().work = runtime_pass<R>([](R& r, const PassSite& p) { r.add_tiles(p.graph, p.env, false); });
        out.push_back({"dof_dilate", "near-field reach over the tiles a blur circle spans", this, {"dof_dilate"}});
        out.back().work = runtime_pass<R>([](R& r, const PassSite& p) { r.add_tiles(p.graph, p.env, true); });
        out.push_back({"dof_gather", "near and far fields, " + std::to_string(o.samples) + " samples each", this, {"dof_gather"}});
        out.back().work = runtime_pass<R>([](R& r, const PassSite& p) { r.add_gather(p.graph, p.env, p.targets); });
    }
    std::vector<ProgramDesc> programs() const override {
        using S = ShaderStage;
        return {{"dof_coc", {{S::vertex, "post/fullscreen.vert"}, {S::fragment, "effects/dof/coc.frag"}}, {}},
                {"dof_tiles", {{S::vertex, "post/fullscreen.vert"}, {S::fragment, "effects/dof/tiles.frag"}}, {}},
                {"dof_dilate", {{S::vertex, "post/fullscreen.vert"}, {S::fragment, "effects/dof/tiles.frag"}}, {"DILATE"}},
                {"dof_gather", {{S::vertex, "post/fullscreen.vert"}, {S::fragment, "effects/dof/gather.frag"}}, {}}};
    }
    std::vector<GpuBlockInfo> gpu_blocks() const override { return {{"DofData", DOF_BINDING, sizeof(gpu::DofData), "dof_gather"}}; }
    std::unique_ptr<EffectRuntime> create_runtime() const override { return std::make_unique<DofRuntime>(); }
    std::vector<AccuracySweep> accuracy_sweeps(bool quick) const override { return dof_accuracy_sweeps(quick); }
};

}  // namespace

const Effect& dof_effect() {
    static const Dof effect;
    return effect;
}

}  // namespace candela
