// Distance fog: the smallest complete effect module (options and a knob, a decision, one pass
// with its own data, a program, a uniform block shared with GLSL). Off by default.
#include <glm/glm.hpp>

#include "effects/effect.hpp"
#include "effects/fog/fog_data.h"
#include "render/features.hpp"
#include "render/passes/pass_env.hpp"

namespace candela {
namespace {

struct FogOptions {
    float density = 0.05f;  // [0, 100] extinction per world unit
};

class FogRuntime final : public EffectRuntime {
public:
    void prepare(const FramePrep& p) override {
        const gpu::FogData d{glm::vec4(p.frame.env_radiance.x, p.frame.env_radiance.y, p.frame.env_radiance.z,
                                       p.settings.get<FogOptions>().density)};
        if (!block_) block_ = gl::Buffer(sizeof d, nullptr, GL_DYNAMIC_STORAGE_BIT);
        block_.update(0, sizeof d, &d);
    }
    void add_pass(const std::string&, FrameGraph& graph, const PassEnv& env, FrameTargets& targets) override {
        struct Data {
            FrameGraph::ResourceId depth = -1, hdr = -1;
        };
        const GLuint program = env.programs.get("fog").id();
        graph.add_pass<Data>(
            "fog",
            [&](FrameGraph::Builder& b, Data& d) {
                d.depth = b.read(targets.depth);
                d.hdr = b.write(targets.hdr);
            },
            [this, &env, program](const Data& d, FrameGraph::Context& ctx) {
                gl::PipelineState ps;
                ps.blend = true;  // hdr = fog + alpha * hdr
                ps.blend_src_rgb = GL_ONE;
                ps.blend_dst_rgb = GL_SRC_ALPHA;
                ps.blend_src_alpha = GL_ZERO;
                ps.blend_dst_alpha = GL_ONE;
                ctx.state.apply(ps);
                ctx.state.bind_framebuffer(env.fbos.get({&ctx.texture(d.hdr)}, nullptr));
                ctx.state.viewport(0, 0, env.width, env.height);
                glBindBufferBase(GL_UNIFORM_BUFFER, 0, env.frame_ubo.id());
                glBindBufferBase(GL_UNIFORM_BUFFER, FOG_BINDING, block_.id());
                glBindTextureUnit(0, ctx.texture(d.depth).id());
                glBindSampler(0, 0);
                ctx.state.use_program(program);
                ctx.state.bind_vertex_array(env.empty_vao.id());
                glDrawArrays(GL_TRIANGLES, 0, 3);
                ++ctx.counters.draw_calls;
                ctx.counters.triangles += 1;
                glBindTextureUnit(0, 0);  // the pool may attach the depth texture next frame
            });
    }

private:
    gl::Buffer block_;
};

class Fog final : public Effect {
public:
    const char* name() const override { return "fog"; }
    bool on_by_default() const override { return false; }
    std::any default_options() const override { return FogOptions{}; }
    std::vector<Knob> knobs() const override {
        return KnobRows<FogOptions>("fog", [](RenderSettings& s) -> FogOptions& { return s.get<FogOptions>(); })
            .real("density", &FogOptions::density, 0.0f, 100.0f, "fog extinction per world unit")
            .rows;
    }
    EffectDecision decide(const Features&, const RenderSettings& s) const override {
        return decide_effect(name(), s.on(name()), s.get<FogOptions>().density > 0.0f, "fog.density > 0", s.gating);
    }
    void plan(Stage stage, const Features& f, const RenderSettings&, std::vector<PlannedPass>& out) const override {
        if (stage == Stage::after_lighting) out.push_back({"fog", f.decision(name()).reason.substr(4), this, {"fog"}});
    }
    std::vector<ProgramDesc> programs() const override {
        return {{"fog", {{ShaderStage::vertex, "post/fullscreen.vert"}, {ShaderStage::fragment, "effects/fog/fog.frag"}}, {}}};
    }
    std::vector<GpuBlockInfo> gpu_blocks() const override { return {{"FogData", FOG_BINDING, sizeof(gpu::FogData), "fog"}}; }
    std::unique_ptr<EffectRuntime> create_runtime() const override { return std::make_unique<FogRuntime>(); }
};

}  // namespace

const Effect& fog_effect() {
    static const Fog effect;
    return effect;
}

}  // namespace candela
