#include "effects/ssao/ssao.hpp"

#include <cmath>

#include "render/features.hpp"
#include "render/passes/pass_env.hpp"
#include "effects/ssao/ssao_sweep.hpp"
#include "effects/ssao/ssao_data.h"
#include "gpu/bindings.h"

namespace candela {
namespace {

// The passes: "ssao" (the AO buffer), then "ssao_blur_x" and "ssao_blur_y" when ssao.blur > 0.
class SsaoRuntime final : public EffectRuntime {
    friend class Ssao;  // its plan hands each pass the member that adds it

public:
    void prepare(const FramePrep& p) override {
        ao_ = -1;
        const SsaoOptions& o = p.settings.get<SsaoOptions>();
        gpu::SsaoData d{};
        d.radius = p.settings.ao.radius;
        d.bias = o.bias;
        d.samples = o.samples;
        d.steps = o.steps;
        d.on = p.decision.planned ? 1 : 0;
        d.blur = o.blur;
        d.downscale = o.resolution == SsaoResolution::half ? 2 : 1;
        if (!block_) block_ = gl::Buffer(sizeof d, nullptr, GL_DYNAMIC_STORAGE_BIT);
        block_.update(0, sizeof d, &d);
        downscale_ = d.downscale;
        if (p.decision.planned && !noise_) make_noise();
    }

    void read_shading_inputs(FrameGraph::Builder& b) const override {
        if (ao_ >= 0) b.read(ao_);
    }

    void bind_shading_inputs(const PassEnv& env, FrameGraph::Context* ctx) const override {
        glBindBufferBase(GL_UNIFORM_BUFFER, SSAO_BINDING, block_.id());
        if (ao_ >= 0 && ctx) {
            glBindTextureUnit(SSAO_UNIT, ctx->texture(ao_).id());
            glBindSampler(SSAO_UNIT, env.linear_clamp.id());
        }
    }

private:
    // The 4x4 rotation tile: angles and step offsets on a stratified, shuffled grid (every pixel
    // of a 4x4 block gets a different rotation; the blur averages the pattern away).
    void make_noise() {
        noise_ = gl::Texture::create_2d(GL_RGBA16F, 4, 4, 1);
        static const int order[16] = {0, 8, 2, 10, 12, 4, 14, 6, 3, 11, 1, 9, 15, 7, 13, 5};  // Bayer 4x4
        std::vector<float> texels(64);
        for (int i = 0; i < 16; ++i) {
            const float angle = 6.28318531f * (static_cast<float>(order[i]) + 0.5f) / 16.0f;
            texels[static_cast<size_t>(i * 4 + 0)] = std::cos(angle);
            texels[static_cast<size_t>(i * 4 + 1)] = std::sin(angle);
            texels[static_cast<size_t>(i * 4 + 2)] = (static_cast<float>(order[(i * 7) % 16]) + 0.5f) / 16.0f;
            texels[static_cast<size_t>(i * 4 + 3)] = 0.0f;
        }
        glTextureSubImage2D(noise_.id(), 0, 0, 0, 4, 4, GL_RGBA, GL_FLOAT, texels.data());
    }

    void fullscreen(const PassEnv& env, FrameGraph::Context& ctx, GLuint fbo, int w, int h, GLuint program) const {
        draw_fullscreen(env, ctx, fbo, w, h, program);
    }

    void add_ao(FrameGraph& graph, const PassEnv& env, const FrameTargets& targets) {
        struct Data {
            FrameGraph::ResourceId depth = -1, normals = -1, ao = -1;
        };
        const GLuint program = env.programs.get("ssao").id();
        const Data& data = graph.add_pass<Data>(
            "ssao",
            [&](FrameGraph::Builder& b, Data& d) {
                d.depth = b.read(targets.depth, SSAO_DEPTH_UNIT);
                d.normals = b.read(targets.normals, SSAO_NORMALS_UNIT);
                const int f = downscale_;
                d.ao = b.create("ssao", {GL_RG16F, (env.width + f - 1) / f, (env.height + f - 1) / f});
            },
            [this, &env, program](const Data& d, FrameGraph::Context& ctx) {
                glBindBufferBase(GL_UNIFORM_BUFFER, FRAME_BINDING, env.frame_ubo.id());
                glBindBufferBase(GL_UNIFORM_BUFFER, SSAO_BINDING, block_.id());
                gl::bind_texture_unit(SSAO_NOISE_UNIT, noise_);
                const TextureDesc& desc = ctx.desc(d.ao);
                fullscreen(env, ctx, env.fbos.get({&ctx.texture(d.ao)}, nullptr), desc.width, desc.height, program);
            });
        ao_ = data.ao;
    }

    // One axis of the blur: reads the AO buffer so far, writes the next one.
    void add_blur(FrameGraph& graph, const PassEnv& env, int axis) {
        struct Data {
            FrameGraph::ResourceId in = -1, out = -1;
        };
        const GLuint program = env.programs.get("ssao_blur").id();
        const char* name = axis == 0 ? "ssao_blur_x" : "ssao_blur_y";
        const Data& data = graph.add_pass<Data>(
            name,
            [&](FrameGraph::Builder& b, Data& d) {
                d.in = b.read(ao_, SSAO_BLUR_IN_UNIT);
                d.out = b.create(name, graph.resources()[static_cast<size_t>(d.in)].desc);
            },
            [this, &env, axis, program](const Data& d, FrameGraph::Context& ctx) {
                glBindBufferBase(GL_UNIFORM_BUFFER, SSAO_BINDING, block_.id());
                glProgramUniform2i(program, 0, axis == 0 ? 1 : 0, axis == 0 ? 0 : 1);
                const TextureDesc& desc = ctx.desc(d.out);
                fullscreen(env, ctx, env.fbos.get({&ctx.texture(d.out)}, nullptr), desc.width, desc.height, program);
            });
        ao_ = data.out;
    }

    gl::Texture noise_;
    gl::Buffer block_;
    int downscale_ = 2;
    FrameGraph::ResourceId ao_ = -1;  // this frame's AO buffer (after the blur passes so far)
};

class Ssao final : public Effect {
public:
    const char* name() const override { return "ssao"; }
    std::any default_options() const override { return SsaoOptions{}; }
    std::vector<Knob> knobs() const override {
        return KnobRows<SsaoOptions>("ssao", [](RenderSettings& s) -> SsaoOptions& { return s.get<SsaoOptions>(); })
            .integer("samples", &SsaoOptions::samples, 1, 256, "SSAO directions per pixel (cosine-distributed around the normal)")
            .while_moving("6")
            .integer("steps", &SsaoOptions::steps, 1, 32, "SSAO steps marched along each direction, out to ao.radius")
            .choice("resolution", &SsaoOptions::resolution, kSsaoResolutions, "resolution of the AO buffer")
            .while_moving("half")
            .integer("blur", &SsaoOptions::blur, 0, 16, "depth-aware blur radius in AO pixels (0: no blur)")
            .while_moving("2")
            .real("bias", &SsaoOptions::bias, 0.0f, 0.5f, "SSAO start offset and depth tolerance, as a fraction of ao.radius")
            .rows;
    }
    // SSAO scales the ambient term (shade_ambient): the environment's light and, where reflection
    // probes run, the surroundings they captured, which a scene without an environment still
    // reflects (a closed room with a glass or metal object).
    EffectDecision decide(const Features& f, const RenderSettings& s) const override {
        const bool probes = f.decision("reflections").planned;
        return decide_effect(name(), s.on(name()) || s.debug.view == DebugView::ao, f.environment || probes,
                             f.environment ? "ambient/environment light to occlude"
                             : probes      ? "reflection probes' light to occlude"
                                           : "no ambient or environment light to occlude",
                             s.gating);
    }
    void plan(Stage stage, const Features& f, const RenderSettings& s, std::vector<PlannedPass>& out) const override {
        if (stage != Stage::screen) return;
        const int blur = s.get<SsaoOptions>().blur;
        using R = SsaoRuntime;
        out.push_back({"ssao", f.decision(name()).reason.substr(4), this, {"ssao"}});
        out.back().work = runtime_pass<R>([](R& r, const PassSite& p) { r.add_ao(p.graph, p.env, p.targets); });
        if (blur > 0) {
            out.push_back({"ssao_blur_x", "ssao.blur=" + std::to_string(blur), this, {"ssao_blur"}});
            out.back().work = runtime_pass<R>([](R& r, const PassSite& p) { r.add_blur(p.graph, p.env, 0); });
            out.push_back({"ssao_blur_y", "ssao.blur=" + std::to_string(blur), this, {"ssao_blur"}});
            out.back().work = runtime_pass<R>([](R& r, const PassSite& p) { r.add_blur(p.graph, p.env, 1); });
        }
    }
    const char* needs_depth_normals() const override { return "SSAO"; }
    std::vector<ProgramDesc> programs() const override {
        using S = ShaderStage;
        return {{"ssao", {{S::vertex, "post/fullscreen.vert"}, {S::fragment, "effects/ssao/ssao.frag"}}, {}},
                {"ssao_blur", {{S::vertex, "post/fullscreen.vert"}, {S::fragment, "effects/ssao/blur.frag"}}, {}}};
    }
    std::vector<GpuBlockInfo> gpu_blocks() const override { return {{"SsaoData", SSAO_BINDING, sizeof(gpu::SsaoData), "ssao"}}; }
    const char* shading_include() const override { return "effects/ssao/ssao_shading.glsl"; }
    std::vector<ShadingHook> shading_hooks() const override { return {ShadingHook::occlusion}; }
    std::unique_ptr<EffectRuntime> create_runtime() const override { return std::make_unique<SsaoRuntime>(); }
    std::vector<AccuracySweep> accuracy_sweeps(bool quick) const override { return ssao_accuracy_sweeps(quick); }
};

}  // namespace

const Effect& ssao_effect() {
    static const Ssao effect;
    return effect;
}

}  // namespace candela
