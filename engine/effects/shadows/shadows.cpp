// Shadow maps: the depth of every caster from each shadow view (shadow_views.hpp), one layer of
// the shadow array per view. Casters are drawn without face culling (closed or not, both sides
// cast) and with slope-scaled polygon offset away from the light; an area-light piece's own
// emitter does not shadow it. BLEND materials cast like opaque ones, as they block rays in the
// ray tracer.
#include "effects/shadows/shadows.hpp"

#include <cmath>

#include <glm/gtc/type_ptr.hpp>

#include "effects/shadows/shadows_data.h"
#include "effects/shadows/shadows_sweep.hpp"
#include "render/features.hpp"
#include "render/passes/pass_env.hpp"

namespace candela {
namespace {

// Whether no point of the box can reach the view: all eight corners lie beyond one side plane of
// the clip volume (x > w, x < -w, y > w or y < -w), by a relative margin far above the rounding of
// the vertex shader's transform. The side distance (x - w, ...) is linear in the position, so every
// point of the box, every vertex of the draw included, lies beyond that plane too: the draw covers
// no texel of the view and skipping it changes no depth. The near and far planes are left alone.
bool outside_view(const glm::mat4& view_proj, const Bounds& b) {
    if (b.empty() || !std::isfinite(b.min.x + b.min.y + b.min.z + b.max.x + b.max.y + b.max.z)) return false;
    constexpr float kMargin = 1e-4f;
    bool out[4] = {true, true, true, true};  // beyond +x, -x, +y, -y
    for (int corner = 0; corner < 8; ++corner) {
        const glm::vec4 c = view_proj * glm::vec4(corner & 1 ? b.max.x : b.min.x, corner & 2 ? b.max.y : b.min.y,
                                                  corner & 4 ? b.max.z : b.min.z, 1.0f);
        const float ax = kMargin * (std::abs(c.x) + std::abs(c.w)), ay = kMargin * (std::abs(c.y) + std::abs(c.w));
        out[0] = out[0] && c.x - c.w > ax;
        out[1] = out[1] && -c.x - c.w > ax;
        out[2] = out[2] && c.y - c.w > ay;
        out[3] = out[3] && -c.y - c.w > ay;
    }
    return out[0] || out[1] || out[2] || out[3];
}

}  // namespace

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
    // The shadow filter (shadows_shading.glsl): only the selected mode's code is compiled.
    defines_.clear();
    if (d.filter_mode >= 0 && d.filter_mode <= 3) defines_.push_back("SHADOW_FILTER_MODE " + std::to_string(d.filter_mode));
    if (!on_) {
        cpu_ = {};
        return;
    }
    const ShadowAtlas& atlas = p.gpu.shadow_atlas();
    const int res = atlas.resolution;
    const int layers = std::max(atlas.layers, 1);
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
        drawn_.clear();
    }
    // A new scene, a new pose or other caster settings: every cached layer is stale.
    if (!options_.cache || drawn_gpu_ != &p.gpu || drawn_pose_ != p.gpu.pose_version() || drawn_slope_bias_ != options_.slope_bias)
        drawn_.clear();
    drawn_gpu_ = &p.gpu;
    drawn_pose_ = p.gpu.pose_version();
    drawn_slope_bias_ = options_.slope_bias;
    drawn_.resize(static_cast<size_t>(p.gpu.shadow_view_count()));
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
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, SHADOW_VIEWS_BINDING, views_.id());
    glBindTextureUnit(SHADOW_UNIT, array_.id());
    glBindSampler(SHADOW_UNIT, compare_.id());
    glBindTextureUnit(SHADOW_DEPTH_UNIT, array_.id());
    glBindSampler(SHADOW_DEPTH_UNIT, raw_.id());
}

void ShadowsRuntime::add_maps(FrameGraph& graph, const PassEnv& env) {
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
            bind_scene_buffers(env);
            ctx.state.bind_vertex_array(env.scene.vertex_array().id());
            const auto& infos = env.scene.light_infos();
            const auto& draws = env.scene.draws();
            // Only MASK casters need a fragment shader (the alpha test); the others are drawn
            // with the depth-only program, which writes the same depth: the depth test keeps the
            // greatest depth whatever the order of the draws, so splitting them changes nothing.
            bool any_masked = false;
            for (const auto& d : draws) any_masked = any_masked || d.alpha_mode == AlphaMode::mask;
            const GLuint depth_program = env.programs.get("shadow_depth").id();
            const GLuint mask_program = any_masked ? env.programs.get("shadow").id() : 0;
            // Draws whose bounds hold all their vertices: rigid ones (a deformed primitive's
            // vertices are posed on the CPU; its bounds are not trusted here).
            const Scene& scene = env.scene.scene();
            std::vector<bool> cullable(draws.size());
            for (size_t di = 0; di < draws.size(); ++di) {
                const Node& node = scene.nodes[static_cast<size_t>(draws[di].node)];
                const Mesh& mesh = scene.meshes[static_cast<size_t>(node.mesh)];
                cullable[di] = !mesh.primitives[static_cast<size_t>(draws[di].primitive)].deformable();
            }
            const auto visible = [&](size_t di, const glm::mat4& view_proj) {
                return !cullable[di] || !outside_view(view_proj, draws[di].world_bounds);
            };
            layers_drawn_ = 0;
            const auto& tiles = env.scene.shadow_atlas().tiles;
            for (size_t layer = 0; layer < cpu_.views.size(); ++layer) {  // `layer`: the view's index
                DrawnLayer& drawn = drawn_[layer];
                const ShadowTile& tile = tiles[layer];
                if (drawn.valid && drawn.view_proj == cpu_.views[layer].view_proj && drawn.tile == tile &&
                    drawn.light == cpu_.light[layer] && drawn.skip == cpu_.skip[layer])
                    continue;  // the depth in the tile is this view's (shadows.cache)
                drawn = {cpu_.views[layer].view_proj, tile, cpu_.light[layer], cpu_.skip[layer], options_.cache};
                ++layers_drawn_;
                ctx.state.bind_framebuffer(layer_fbos_[static_cast<size_t>(tile.layer)].id());
                ctx.state.viewport(tile.x, tile.y, tile.size, tile.size);
                // Clear the tile alone: the layer's other tiles may hold other views.
                glEnable(GL_SCISSOR_TEST);
                glScissor(tile.x, tile.y, tile.size, tile.size);
                const float clear_depth = 0.0f;  // reversed-Z far: lit
                glClearBufferfv(GL_DEPTH, 0, &clear_depth);
                glDisable(GL_SCISSOR_TEST);
                if (cpu_.skip[layer]) continue;
                const int own = infos[static_cast<size_t>(cpu_.light[layer])].own_draw;
                const glm::mat4& view_proj = cpu_.views[layer].view_proj;
                glProgramUniformMatrix4fv(depth_program, 4, 1, GL_FALSE, glm::value_ptr(view_proj));
                ctx.state.use_program(depth_program);
                for (size_t di = 0; di < draws.size(); ++di) {
                    const GpuScene::Draw& d = draws[di];
                    if (static_cast<int>(di) == own || d.alpha_mode == AlphaMode::mask || !visible(di, view_proj))
                        continue;
                    // draw_item without the material's uniforms and textures, which this program
                    // does not have.
                    ctx.state.set_cull(false, GL_BACK);
                    ctx.state.set_front_face(d.mirrored ? GL_CW : GL_CCW);
                    glProgramUniformMatrix4fv(depth_program, 0, 1, GL_FALSE, glm::value_ptr(d.model));
                    glDrawElementsBaseVertex(GL_TRIANGLES, d.index_count, GL_UNSIGNED_INT,
                                             reinterpret_cast<const void*>(d.first_index * sizeof(std::uint32_t)),
                                             d.base_vertex);
                    ++ctx.counters.draw_calls;
                    ctx.counters.triangles += static_cast<std::size_t>(d.index_count / 3);
                }
                if (!mask_program) continue;
                glProgramUniformMatrix4fv(mask_program, 4, 1, GL_FALSE, glm::value_ptr(view_proj));
                ctx.state.use_program(mask_program);
                for (size_t di = 0; di < draws.size(); ++di)
                    if (static_cast<int>(di) != own && draws[di].alpha_mode == AlphaMode::mask &&
                        visible(di, view_proj))
                        draw_item(env, ctx, draws[di], false, GL_BACK, mask_program, true);
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
            .integer("resolution", &O::resolution, 64, 8192, "texels per side of a full-resolution shadow view (a layer of the atlas)")
            .choice("filter", &O::filter, kShadowFilters,
                    "hard: one 2x2 hardware PCF tap; pcf: pcf_size^2 taps; pcss: blocker search + variable kernel")
            .integer("pcf_size", &O::pcf_size, 1, 15, "PCF kernel width in taps (each tap is a 2x2 hardware PCF)")
            .while_moving("3")
            .integer("pcss_blocker_taps", &O::pcss_blocker_taps, 1, 128, "PCSS blocker-search taps")
            .while_moving("4")
            .integer("pcss_taps", &O::pcss_taps, 1, 256, "PCSS filter taps")
            .while_moving("8")
            .real("max_radius", &O::max_radius, 1.0f, 64.0f, "largest PCSS search/filter radius in texels")
            .real("normal_bias", &O::normal_bias, 0.0f, 16.0f, "receiver offset along its normal, in shadow texels")
            .real("depth_bias", &O::depth_bias, 0.0f, 16.0f, "receiver depth moved towards the light, in shadow texels")
            .real("slope_bias", &O::slope_bias, 0.0f, 16.0f, "slope-scaled polygon offset factor of the caster pass")
            .real("receiver_slope_bias", &O::receiver_slope_bias, 0.0f, 4.0f,
                  "extra depth bias of a filter tap r texels out: r * tan(theta) texels times this")
            .integer("cascades", &O::cascades, 1, 4, "cascades of a directional light's shadow map")
            .integer("max_lights", &O::max_lights, 0, 4096,
                     "shadow-casting lights at most: directional first, then by intensity over squared distance from the camera")
            .integer("budget_mb", &O::budget_mb, 16, 16384,
                     "shadow-map memory at most; past it lower-priority lights get smaller tiles, then no shadow")
            .real("split_lambda", &O::split_lambda, 0.0f, 1.0f, "cascade split blend: 0 uniform, 1 logarithmic")
            .boolean("cache", &O::cache, "keep a shadow view's depth while its view, the pose and the caster settings are unchanged")
            .rows;
    }
    EffectDecision decide(const Features& f, const RenderSettings& s) const override {
        return decide_effect(name(), s.on(name()), f.scene.shadows.needed, f.scene.shadows.reason, s.gating);
    }
    void plan(Stage stage, const Features& f, const RenderSettings&, std::vector<PlannedPass>& out) const override {
        if (stage != Stage::light_views) return;
        // The alpha-testing caster program only when some material is MASK (ShadowsRuntime::add_maps).
        bool masked = f.source == nullptr;
        if (f.source)
            for (const Material& m : f.source->materials) masked = masked || m.alpha_mode == AlphaMode::mask;
        std::vector<std::string> programs{"shadow_depth"};
        if (masked) programs.push_back("shadow");
        out.push_back({"shadow_maps", f.decision(name()).reason.substr(4), this, programs});
        using R = ShadowsRuntime;
        out.back().work = runtime_pass<R>([](R& r, const PassSite& p) { r.add_maps(p.graph, p.env); });
    }
    void light_setup(const RenderSettings& s, const EffectDecision& d, LightSetup& out) const override {
        const ShadowsOptions& o = s.get<ShadowsOptions>();
        out.shadows = d.planned;
        out.cascades = o.cascades;
        out.max_shadowed = o.max_lights;
        out.shadow_resolution = o.resolution;
        out.shadow_budget_mb = o.budget_mb;
    }
    std::vector<ProgramDesc> programs() const override {
        using S = ShaderStage;
        return {{"shadow",
                 {{S::vertex, "effects/shadows/caster.vert"}, {S::fragment, "effects/shadows/caster.frag"}},
                 {}},
                {"shadow_depth",
                 {{S::vertex, "effects/shadows/caster.vert"}, {S::fragment, "effects/shadows/caster.frag"}},
                 {"CASTER_DEPTH_ONLY"}}};
    }
    std::vector<GpuBlockInfo> gpu_blocks() const override { return {{"ShadowsData", SHADOWS_BINDING, sizeof(gpu::ShadowsData), "forward"}}; }
    const char* shading_include() const override { return "effects/shadows/shadows_shading.glsl"; }
    std::vector<ShadingHook> shading_hooks() const override { return {ShadingHook::light_visibility}; }
    std::unique_ptr<EffectRuntime> create_runtime() const override { return std::make_unique<ShadowsRuntime>(); }
    std::vector<AccuracySweep> accuracy_sweeps(bool quick) const override { return shadows_accuracy_sweeps(quick); }
};

}  // namespace

const Effect& shadows_effect() {
    static const Shadows effect;
    return effect;
}

}  // namespace candela
