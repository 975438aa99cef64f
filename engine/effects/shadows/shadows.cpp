// Shadow maps: the depth of every caster from each shadow view (shadow_views.hpp), one layer of
// the shadow array per view. Casters are drawn without face culling (closed or not, both sides
// cast) and with slope-scaled polygon offset away from the light; an area-light piece's own
// emitter does not shadow it. BLEND materials cast like opaque ones, as they block rays in the
// ray tracer.
#include "effects/shadows/shadows.hpp"

#include <glm/gtc/type_ptr.hpp>

#include "effects/shadows/shadows_data.h"
#include "effects/shadows/shadows_sweep.hpp"
#include "render/features.hpp"
#include "render/passes/pass_env.hpp"

namespace candela {

void ShadowsRuntime::prepare(const FramePrep& p) {
    options_ = p.settings.get<ShadowsOptions>();
    on_ = p.decision.planned;
    maps_ = -1;
    gpu::ShadowsData d{};
    if (on_) {
        d.filter_mode = static_cast<int>(options_.filter);
        d.pcf_size = options_.pcf_size;
        d.blocker_taps = options_.pcss_blocker_taps;
        d.pcss_taps = options_.pcss_taps;
        d.normal_bias = options_.normal_bias;
        d.depth_bias = options_.depth_bias;
        d.resolution = static_cast<float>(options_.resolution);
        d.max_radius = options_.max_radius;
        d.receiver_slope_bias = options_.receiver_slope_bias;
    }
    if (!block_) block_ = gl::Buffer(sizeof d, nullptr, GL_DYNAMIC_STORAGE_BIT);
    block_.update(0, sizeof d, &d);
    if (!on_) {
        cpu_ = {};
        return;
    }
    const int res = options_.resolution;
    const int layers = std::max(p.gpu.shadow_view_count(), 1);
    if (resolution_ != res || layers_ != layers) {
        GLuint id = 0;
        glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &id);
        glTextureStorage3D(id, 1, GL_DEPTH_COMPONENT32F, res, res, layers);
        array_ = gl::Texture::adopt(id, res, res, GL_DEPTH_COMPONENT32F);
        layer_fbos_.clear();
        for (int layer = 0; layer < layers; ++layer) {
            gl::Framebuffer fbo = gl::Framebuffer::create();
            glNamedFramebufferTextureLayer(fbo.id(), GL_DEPTH_ATTACHMENT, id, 0, layer);
            glNamedFramebufferDrawBuffer(fbo.id(), GL_NONE);
            fbo.check_complete("shadow map layer");
            layer_fbos_.push_back(std::move(fbo));
        }
        resolution_ = res;
        layers_ = layers;
    }
    if (!compare_) {
        compare_ = gl::Sampler::create(GL_LINEAR, GL_LINEAR, GL_CLAMP_TO_EDGE, GL_CLAMP_TO_EDGE);
        glSamplerParameteri(compare_.id(), GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
        glSamplerParameteri(compare_.id(), GL_TEXTURE_COMPARE_FUNC, GL_GEQUAL);  // lit: ref >= stored (reversed-Z)
        raw_ = gl::Sampler::create(GL_NEAREST, GL_NEAREST, GL_CLAMP_TO_EDGE, GL_CLAMP_TO_EDGE);
    }
    cpu_ = build_shadow_views(p.gpu, p.scene_bounds, p.camera, p.aspect, options_);
    std::vector<ShadowViewData> views = cpu_.views;
    if (views.empty()) views.push_back({});
    const auto bytes = static_cast<GLsizeiptr>(views.size() * sizeof(ShadowViewData));
    if (!views_ || views_bytes_ != bytes) {
        views_ = gl::Buffer(bytes, nullptr, GL_DYNAMIC_STORAGE_BIT);
        views_bytes_ = bytes;
    }
    views_.update(0, bytes, views.data());
}

void ShadowsRuntime::begin_graph(FrameGraph& graph) {
    if (on_) maps_ = graph.import_texture("shadow_maps", array_, {GL_DEPTH_COMPONENT32F, resolution_, resolution_});
}

void ShadowsRuntime::read_shading_inputs(FrameGraph::Builder& b) const {
    if (maps_ >= 0) b.read(maps_);
}

void ShadowsRuntime::bind_shading_inputs(const PassEnv&, FrameGraph::Context*) const {
    glBindBufferBase(GL_UNIFORM_BUFFER, SHADOWS_BINDING, block_.id());
    if (!on_) return;
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, views_.id());
    glBindTextureUnit(7, array_.id());
    glBindSampler(7, compare_.id());
    glBindTextureUnit(8, array_.id());
    glBindSampler(8, raw_.id());
}

void ShadowsRuntime::add_pass(const std::string&, FrameGraph& graph, const PassEnv& env, FrameTargets&) {
    graph.add_pass(
        "shadow_maps", [&](FrameGraph::Builder& b) { b.write(maps_); },
        [this, &env](FrameGraph::Context& ctx) {
            gl::PipelineState ps;
            ps.depth_test = true;
            ps.depth_func = GL_GREATER;
            ps.color_write = false;
            ps.polygon_offset_factor = -options_.slope_bias;
            ps.polygon_offset_units = -1.0f;
            ctx.state.apply(ps);
            ctx.state.viewport(0, 0, resolution_, resolution_);
            bind_scene_buffers(env);
            const GLuint program = env.programs.get("shadow").id();
            ctx.state.use_program(program);
            ctx.state.bind_vertex_array(env.scene.vertex_array().id());
            const auto& infos = env.scene.light_infos();
            for (size_t layer = 0; layer < cpu_.views.size(); ++layer) {
                ctx.state.bind_framebuffer(layer_fbos_[layer].id());
                const float clear_depth = 0.0f;  // reversed-Z far: lit
                glClearBufferfv(GL_DEPTH, 0, &clear_depth);
                if (cpu_.skip[layer]) continue;
                glProgramUniformMatrix4fv(program, 4, 1, GL_FALSE, glm::value_ptr(cpu_.views[layer].view_proj));
                const int own = infos[static_cast<size_t>(cpu_.light[layer])].own_draw;
                const auto& draws = env.scene.draws();
                for (size_t di = 0; di < draws.size(); ++di)
                    if (static_cast<int>(di) != own) draw_item(env, ctx, draws[di], false, GL_BACK, program, true);
            }
        });
}

namespace {

class Shadows final : public Effect {
public:
    const char* name() const override { return "shadows"; }
    std::any default_options() const override { return ShadowsOptions{}; }
    std::vector<Knob> knobs() const override {
        using O = ShadowsOptions;
        return KnobRows<O>("shadows", [](RenderSettings& s) -> O& { return s.get<O>(); })
            .integer("resolution", &O::resolution, 64, 8192, "texels per side of every shadow view")
            .choice("filter", &O::filter, kShadowFilters,
                    "hard: one 2x2 hardware PCF tap; pcf: pcf_size^2 taps; pcss: blocker search + variable kernel")
            .integer("pcf_size", &O::pcf_size, 1, 15, "PCF kernel width in taps (each tap is a 2x2 hardware PCF)")
            .integer("pcss_blocker_taps", &O::pcss_blocker_taps, 1, 128, "PCSS blocker-search taps")
            .integer("pcss_taps", &O::pcss_taps, 1, 256, "PCSS filter taps")
            .real("max_radius", &O::max_radius, 1.0f, 64.0f, "largest PCSS search/filter radius in texels")
            .real("normal_bias", &O::normal_bias, 0.0f, 16.0f, "receiver offset along its normal, in shadow texels")
            .real("depth_bias", &O::depth_bias, 0.0f, 16.0f, "receiver depth moved towards the light, in shadow texels")
            .real("slope_bias", &O::slope_bias, 0.0f, 16.0f, "slope-scaled polygon offset factor of the caster pass")
            .real("receiver_slope_bias", &O::receiver_slope_bias, 0.0f, 4.0f,
                  "extra depth bias of a filter tap r texels out: r * tan(theta) texels times this")
            .integer("cascades", &O::cascades, 1, 4, "cascades of a directional light's shadow map")
            .integer("max_lights", &O::max_lights, 0, 4096, "shadow-casting lights at most: directional first, then the brightest")
            .real("split_lambda", &O::split_lambda, 0.0f, 1.0f, "cascade split blend: 0 uniform, 1 logarithmic")
            .rows;
    }
    EffectDecision decide(const Features& f, const RenderSettings& s) const override {
        return decide_effect(name(), s.on(name()), f.scene.shadows.needed, f.scene.shadows.reason, s.gating);
    }
    void plan(Stage stage, const Features& f, const RenderSettings&, std::vector<PlannedPass>& out) const override {
        if (stage == Stage::light_views) out.push_back({"shadow_maps", f.decision(name()).reason.substr(4), this, {"shadow"}});
    }
    void light_setup(const RenderSettings& s, const EffectDecision& d, LightSetup& out) const override {
        const ShadowsOptions& o = s.get<ShadowsOptions>();
        out.shadows = d.planned;
        out.cascades = o.cascades;
        out.max_shadowed = o.max_lights;
    }
    std::vector<ProgramDesc> programs() const override {
        using S = ShaderStage;
        return {{"shadow", {{S::vertex, "effects/shadows/caster.vert"}, {S::fragment, "effects/shadows/caster.frag"}}, {}}};
    }
    std::vector<GpuBlockInfo> gpu_blocks() const override { return {{"ShadowsData", SHADOWS_BINDING, sizeof(gpu::ShadowsData), "forward"}}; }
    std::unique_ptr<EffectRuntime> create_runtime() const override { return std::make_unique<ShadowsRuntime>(); }
    std::vector<AccuracySweep> accuracy_sweeps(bool quick) const override { return shadows_accuracy_sweeps(quick); }
};

}  // namespace

const Effect& shadows_effect() {
    static const Shadows effect;
    return effect;
}

}  // namespace candela
