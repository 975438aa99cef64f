// Reflective shadow maps (Dachsbacher & Stamminger 2005) and their gather: the RSM pass renders,
// for each RSM light, its shadow views again at rsm.resolution with position, normal and
// reflected flux; the gather pass sums rsm.samples texels per pixel into one-bounce irradiance at
// rsm.gather resolution, which the lighting upsamples and adds through the Lambert term
// (rsm_shading.glsl).
#include "effects/rsm/rsm.hpp"

#include <algorithm>

#include <glm/gtc/type_ptr.hpp>

#include "effects/area_lights/area_lights.hpp"
#include "effects/rsm/rsm_data.h"
#include "effects/rsm/rsm_sweep.hpp"
#include "effects/shadows/shadows.hpp"
#include "render/features.hpp"
#include "render/passes/pass_env.hpp"

namespace candela {
namespace {

constexpr float kPi = 3.14159265358979f;

int downscale(RsmGather g) { return g == RsmGather::quarter ? 4 : g == RsmGather::half ? 2 : 1; }

// The passes: "rsm" (the maps, light_views stage) and "rsm_indirect" (the gather, screen stage).
class RsmRuntime final : public EffectRuntime {
    friend class Rsm;  // its plan hands each pass the member that adds it

public:
    void prepare(const FramePrep& p) override {
        options_ = p.settings.get<RsmOptions>();
        on_ = p.decision.planned;
        maps_ = indirect_ = -1;
        gpu::RsmData d{};
        d.on = on_ ? 1 : 0;
        d.downscale = downscale(options_.gather);
        if (!block_) {
            block_ = gl::Buffer(sizeof d, nullptr, GL_DYNAMIC_STORAGE_BIT);
            nearest_ = gl::Sampler::create(GL_NEAREST, GL_NEAREST, GL_CLAMP_TO_EDGE, GL_CLAMP_TO_EDGE);
        }
        block_.update(0, sizeof d, &d);
        defines_.clear();
        if (d.on == 0) defines_.push_back("RSM_OFF");  // the lighting leaves the gather's read out
        if (on_) prepare_maps(p);
    }
    std::vector<std::string> shading_defines() const override { return defines_; }

    void begin_graph(FrameGraph& graph) override {
        if (on_) maps_ = graph.import_texture("rsm", res_.position, {GL_RGBA32F, res_.resolution, res_.resolution});
    }

    void read_shading_inputs(FrameGraph::Builder& b) const override {
        if (indirect_ >= 0) b.read(indirect_);
    }

    void bind_shading_inputs(const PassEnv& env, FrameGraph::Context* ctx) const override {
        glBindBufferBase(GL_UNIFORM_BUFFER, RSM_BINDING, block_.id());
        if (ctx && indirect_ >= 0) {
            glBindTextureUnit(RSM_INDIRECT_UNIT, ctx->texture(indirect_).id());
            glBindSampler(RSM_INDIRECT_UNIT, env.linear_clamp.id());
        }
    }

    void inspectables(std::vector<std::pair<std::string, const gl::Texture*>>& out) const override {
        if (res_.flux) out.emplace_back("rsm_flux", &res_.flux);
    }

private:
    // An RSM light: a punctual light, or an area light (one emissive draw) as some of its
    // shadowed pieces, whose views share one gather budget.
    struct RsmLight {
        std::vector<int> lights;  // indices into the light buffer
        float priority = 0.0f;    // emitted flux (rgb sum, W); directional lights first
        float flux_scale = 1.0f;  // the emitter's power over its pieces' here (unchosen pieces)
    };

    // The RSM lights: punctual lights with shadow views and area lights with shadowed pieces,
    // directional first, then by emitted flux (point/spot 4 pi I; area pi Le A).
    std::vector<RsmLight> rsm_lights(const FramePrep& p) const {
        const auto& infos = p.gpu.light_infos();
        const auto placed = p.gpu.scene().placed_lights();
        std::vector<RsmLight> out;
        for (int i = 0; i < p.gpu.punctual_light_count(); ++i) {
            if (infos[static_cast<size_t>(i)].view_count <= 0) continue;
            const Light& l = *placed[static_cast<size_t>(i)].light;
            RsmLight rl;
            rl.lights = {i};
            rl.priority = l.type == LightType::directional ? 1e30f : 4.0f * kPi * (l.color.r + l.color.g + l.color.b) * l.intensity;
            out.push_back(std::move(rl));
        }
        // The pieces follow the punctual lights, each emitter's consecutively (GpuScene::update_lights).
        const Scene& scene = p.gpu.scene();
        const int count = static_cast<int>(infos.size());
        for (int i = p.gpu.punctual_light_count(); i < count;) {
            const int draw = infos[static_cast<size_t>(i)].own_draw;
            int end = i;
            float area_all = 0.0f;
            std::vector<int> shadowed;
            for (; end < count && infos[static_cast<size_t>(end)].own_draw == draw; ++end) {
                const LightInfo& info = infos[static_cast<size_t>(end)];
                area_all += info.size * info.size;
                if (info.view_count > 0) shadowed.push_back(end);
            }
            i = end;
            if (shadowed.empty() || draw < 0) continue;
            // At most rsm.area_pieces of them, spread evenly over the emitter's piece order.
            RsmLight rl;
            const size_t n = std::min(shadowed.size(), static_cast<size_t>(options_.area_pieces));
            float area_chosen = 0.0f;
            for (size_t k = 0; k < n; ++k) {
                const int li = shadowed[k * shadowed.size() / n];
                rl.lights.push_back(li);
                area_chosen += infos[static_cast<size_t>(li)].size * infos[static_cast<size_t>(li)].size;
            }
            if (!(area_chosen > 0.0f)) continue;
            rl.flux_scale = area_all / area_chosen;
            const GpuScene::Draw& d = p.gpu.draws()[static_cast<size_t>(draw)];
            const Node& node = scene.nodes[static_cast<size_t>(d.node)];
            const Material& m = scene.material(scene.meshes[static_cast<size_t>(node.mesh)].primitives[static_cast<size_t>(d.primitive)].material);
            const glm::vec3 le = m.emission();
            rl.priority = kPi * (le.r + le.g + le.b) * area_all;
            out.push_back(std::move(rl));
        }
        std::stable_sort(out.begin(), out.end(), [](const RsmLight& a, const RsmLight& b) { return a.priority > b.priority; });
        if (out.size() > static_cast<size_t>(options_.max_lights)) out.resize(static_cast<size_t>(options_.max_lights));
        return out;
    }

    // The RSM views: per RSM light, its shadow views at rsm.resolution (a directional light: one
    // view of the whole scene; an area light: the faces of its chosen pieces that it emits into).
    void prepare_maps(const FramePrep& p) {
        const ShadowsRuntime* shadows = p.runtime<ShadowsRuntime>();
        const ShadowViews& shadow_views = shadows->views();

        Resources& r = res_;
        const auto& infos = p.gpu.light_infos();
        r.views.clear();
        r.kind_texel.clear();
        r.own_draw.clear();
        r.light_first.clear();
        for (const RsmLight& rl : rsm_lights(p)) {
            const int first = static_cast<int>(r.views.size());
            for (int li : rl.lights) {
                const LightInfo& info = infos[static_cast<size_t>(li)];
                // A directional light's RSM covers the whole scene (bounce surfaces outside the view
                // light what is in it); spot, point lights and area pieces reuse their shadow views.
                const bool directional = info.kind == LightInfo::Kind::directional;
                const int count = directional ? 1 : info.view_count;
                for (int k = 0; k < count; ++k) {
                    const size_t layer = static_cast<size_t>(info.first_view + k);
                    if (!directional && layer < shadow_views.skip.size() && shadow_views.skip[layer]) continue;  // behind a one-sided emitter
                    const ShadowViewData sv =
                        directional ? directional_scene_view(info.direction, p.scene_bounds, options_.resolution) : shadow_views.views[layer];
                    // Cube faces: their tangent half-width (a guard band beyond 90 degrees), for the gather.
                    // (A shadow view's texel size is that of its tile's resolution.)
                    const float half_width = count == 6 ? sv.texel_size * sv.tile_texels * 0.5f : 0.0f;
                    const float scale = directional ? 1.0f : sv.tile_texels / static_cast<float>(options_.resolution);
                    r.views.push_back({sv.view_proj, static_cast<float>(li), static_cast<float>(first), 0.0f, half_width});
                    r.kind_texel.push_back(glm::vec4(sv.kind, sv.texel_size * scale, rl.flux_scale, 0.0f));
                    r.own_draw.push_back(info.own_draw);
                }
            }
            const int layers = static_cast<int>(r.views.size()) - first;
            if (layers == 0) continue;
            for (int k = first; k < first + layers; ++k) r.views[static_cast<size_t>(k)].layer_count = static_cast<float>(layers);
            r.light_first.push_back(first);
        }
        const int res = options_.resolution;
        const int layers = std::max<int>(1, static_cast<int>(r.views.size()));
        if (r.resolution != res || r.layers != layers) {
            auto make = [&](GLenum format) {
                GLuint id = 0;
                glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &id);
                glTextureStorage3D(id, 1, format, res, res, layers);
                return gl::Texture::adopt(id, res, res, format);
            };
            r.position = make(GL_RGBA32F);
            r.normal = make(GL_RGBA16F);
            r.flux = make(GL_RGBA16F);
            r.depth = make(GL_DEPTH_COMPONENT32F);
            r.layer_fbos.clear();
            for (int layer = 0; layer < layers; ++layer) {
                gl::Framebuffer fbo = gl::Framebuffer::create();
                const GLuint colors[3] = {r.position.id(), r.normal.id(), r.flux.id()};
                for (int i = 0; i < 3; ++i)
                    glNamedFramebufferTextureLayer(fbo.id(), GL_COLOR_ATTACHMENT0 + static_cast<GLenum>(i), colors[i], 0, layer);
                glNamedFramebufferTextureLayer(fbo.id(), GL_DEPTH_ATTACHMENT, r.depth.id(), 0, layer);
                const GLenum buffers[3] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2};
                glNamedFramebufferDrawBuffers(fbo.id(), 3, buffers);
                fbo.check_complete("reflective shadow map layer");
                r.layer_fbos.push_back(std::move(fbo));
            }
            r.resolution = res;
            r.layers = layers;
        }
        std::vector<Resources::View> views = r.views;
        if (views.empty()) views.push_back({});
        const auto bytes = static_cast<GLsizeiptr>(views.size() * sizeof(Resources::View));
        if (!r.views_buffer || r.views_bytes != bytes) {
            r.views_buffer = gl::Buffer(bytes, nullptr, GL_DYNAMIC_STORAGE_BIT);
            r.views_bytes = bytes;
        }
        r.views_buffer.update(0, bytes, views.data());
    }

    void add_maps(FrameGraph& graph, const PassEnv& env) {
        graph.add_pass(
            "rsm", [&](FrameGraph::Builder& b) { b.write(maps_); },
            [this, &env](FrameGraph::Context& ctx) {
                const Resources& r = res_;
                gl::PipelineState ps;
                ps.depth_test = true;
                ctx.state.apply(ps);
                ctx.state.viewport(0, 0, r.resolution, r.resolution);
                bind_scene_buffers(env);
                const GLuint program = env.programs.get("rsm").id();
                ctx.state.use_program(program);
                ctx.state.bind_vertex_array(env.scene.vertex_array().id());
                for (size_t layer = 0; layer < r.views.size(); ++layer) {
                    ctx.state.bind_framebuffer(r.layer_fbos[layer].id());
                    const float zero[4] = {0, 0, 0, 0};
                    for (int i = 0; i < 3; ++i) glClearBufferfv(GL_COLOR, i, zero);
                    const float clear_depth = 0.0f;
                    glClearBufferfv(GL_DEPTH, 0, &clear_depth);
                    const glm::mat4& vp = r.views[layer].view_proj;
                    glProgramUniformMatrix4fv(program, 4, 1, GL_FALSE, glm::value_ptr(vp));
                    glProgramUniform1i(program, 5, static_cast<int>(r.views[layer].light));
                    glProgramUniform4fv(program, 6, 1, glm::value_ptr(r.kind_texel[layer]));
                    // Perspective: clip w = distance along the view axis, so row 3 of the matrix is it.
                    const glm::vec3 axis(vp[0][3], vp[1][3], vp[2][3]);
                    glProgramUniform3fv(program, 7, 1, glm::value_ptr(axis));
                    // An area piece's own emitter lies in the plane of its views' origin: it neither
                    // reflects that light nor may it hide what it shines on.
                    const auto& draws = env.scene.draws();
                    for (size_t di = 0; di < draws.size(); ++di)
                        if (static_cast<int>(di) != r.own_draw[layer]) draw_item(env, ctx, draws[di], false, GL_BACK, program);
                }
            });
    }

    void add_gather(FrameGraph& graph, const PassEnv& env, const FrameTargets& targets) {
        struct Data {
            FrameGraph::ResourceId depth = -1, normals = -1, out = -1;
        };
        const Data& data = graph.add_pass<Data>(
            "rsm_indirect",
            [&](FrameGraph::Builder& b, Data& d) {
                d.depth = b.read(targets.depth, RSM_DEPTH_UNIT);
                d.normals = b.read(targets.normals, RSM_NORMALS_UNIT);
                b.read(maps_);
                const int f = downscale(options_.gather);
                d.out = b.create("rsm_indirect", {GL_RGBA16F, (env.width + f - 1) / f, (env.height + f - 1) / f});
            },
            [this, &env](const Data& d, FrameGraph::Context& ctx) {
                const Resources& r = res_;
                bind_scene_buffers(env);
                const gl::Texture* maps[3] = {&r.position, &r.normal, &r.flux};
                for (int i = 0; i < 3; ++i) {
                    glBindTextureUnit(static_cast<GLuint>(RSM_POSITION_UNIT + i), maps[i]->id());
                    glBindSampler(static_cast<GLuint>(RSM_POSITION_UNIT + i), nearest_.id());  // nearest: never blend two surfaces
                }
                glBindBufferBase(GL_SHADER_STORAGE_BUFFER, RSM_VIEWS_BINDING, r.views_buffer.id());
                const GLuint program = env.programs.get("rsm_gather").id();
                const int f = downscale(options_.gather);
                glProgramUniform1i(program, 0, static_cast<int>(r.light_first.size()));
                glProgramUniform4i(program, 1, r.resolution, options_.samples, f, 0);
                glProgramUniform1f(program, 2, options_.radius);
                std::vector<int> first(8, 0);
                std::copy_n(r.light_first.begin(), std::min<size_t>(8, r.light_first.size()), first.begin());
                glProgramUniform1iv(program, 3, 8, first.data());
                gl::PipelineState ps;
                ctx.state.apply(ps);
                const TextureDesc& desc = ctx.desc(d.out);
                ctx.state.bind_framebuffer(env.fbos.get({&ctx.texture(d.out)}, nullptr));
                ctx.state.viewport(0, 0, desc.width, desc.height);
                ctx.state.use_program(program);
                ctx.state.bind_vertex_array(env.empty_vao.id());
                glDrawArrays(GL_TRIANGLES, 0, 3);
                ++ctx.counters.draw_calls;
                ctx.counters.triangles += 1;
            });
        indirect_ = data.out;
    }

    // Reflective shadow maps: per layer one light view (a shadow view at rsm.resolution).
    struct Resources {
        gl::Texture position, normal, flux, depth;  // 2D arrays, one layer per view
        std::vector<gl::Framebuffer> layer_fbos;
        using View = gpu::RsmView;
        std::vector<View> views;
        std::vector<glm::vec4> kind_texel;  // per layer: x kind (0 ortho), y texel size at rsm.resolution,
                                            // z flux scale (an area light's unchosen pieces)
        std::vector<int> own_draw;          // per layer: the area piece's emitter (not drawn), -1 none
        std::vector<int> light_first;       // first layer of each RSM light (its layers are consecutive)
        gl::Buffer views_buffer;
        GLsizeiptr views_bytes = 0;
        int resolution = 0, layers = 0;
    } res_;
    RsmOptions options_;
    bool on_ = false;
    gl::Buffer block_;
    std::vector<std::string> defines_;  // shading_defines: from the block
    gl::Sampler nearest_;  // never blend two surfaces of a map
    FrameGraph::ResourceId maps_ = -1, indirect_ = -1;
};

class Rsm final : public Effect {
public:
    const char* name() const override { return "rsm"; }
    bool on_by_default() const override { return false; }  // indirect light costs the most; opt-in
    std::any default_options() const override { return RsmOptions{}; }
    std::vector<Knob> knobs() const override {
        using O = RsmOptions;
        return KnobRows<O>("rsm", [](RenderSettings& s) -> O& { return s.get<O>(); })
            .integer("resolution", &O::resolution, 16, 4096, "texels per side of each light's reflective shadow map")
            .integer("samples", &O::samples, 1, 1024, "RSM texels gathered per pixel and light")
            .while_moving("16")
            .choice("gather", &O::gather, kRsmGathers, "resolution of the RSM gather pass")
            .while_moving("quarter")
            .real("radius", &O::radius, 1e-3f, 1.0f, "RSM sampling radius, as a fraction of the map's width")
            .integer("max_lights", &O::max_lights, 1, 8, "lights with a reflective shadow map: directional first, then the brightest (an area light counts once)")
            .integer("area_pieces", &O::area_pieces, 1, 64, "shadowed pieces of an area light with RSM views (they carry the others' flux)")
            .rows;
    }
    // RSM renders from the lights' shadow views: it needs the shadow pass and a punctual light
    // or an emitter (whose pieces get cube shadow views like point lights).
    EffectDecision decide(const Features& f, const RenderSettings& s) const override {
        const bool shadows = f.decision("shadows").planned;
        const int area = f.scene.emissive_primitives;
        // The GI probes (effects/gi, decided before RSM) carry every bounce, the first included.
        const bool gi = f.decision("gi").planned;
        const bool needed = !gi && shadows && (f.punctual_lights > 0 || area > 0) && s.get<ShadowsOptions>().max_lights > 0;
        std::string what;
        if (gi) {
            what = "the GI probes carry every bounce of indirect light (RSM would add the first one twice)";
        } else if (needed) {
            const int rsm_lights = std::min(f.punctual_lights + area, s.get<RsmOptions>().max_lights);
            what = std::to_string(rsm_lights) + " shadowed light(s) to bounce:";
            if (f.punctual_lights > 0) what += " " + std::to_string(f.punctual_lights) + " punctual" + (area > 0 ? "," : "");
            if (area > 0)
                what += " " + std::to_string(area) + " area (up to " +
                        std::to_string(std::min(s.get<RsmOptions>().area_pieces, s.get<AreaLightsOptions>().samples)) +
                        " shadowed pieces each)";
        } else {
            what = f.punctual_lights + area == 0 ? "no punctual or area light" : "no shadow pass for the RSM to reuse the light views of";
        }
        return decide_effect(name(), s.on(name()) || s.debug.view == DebugView::indirect, needed, what,
                             s.gating || !shadows || gi);  // without shadow views there is nothing to run it on
    }
    void plan(Stage stage, const Features& f, const RenderSettings& s, std::vector<PlannedPass>& out) const override {
        using R = RsmRuntime;
        if (stage == Stage::light_views) {
            out.push_back({"rsm", f.decision(name()).reason.substr(4), this, {"rsm"}});
            out.back().work = runtime_pass<R>([](R& r, const PassSite& p) { r.add_maps(p.graph, p.env); });
        }
        if (stage == Stage::screen) {
            out.push_back({"rsm_indirect",
                           std::string("gather rsm.samples texels per pixel, rsm.gather=") + choice_name(kRsmGathers, s.get<RsmOptions>().gather),
                           this, {"rsm_gather"}});
            out.back().work = runtime_pass<R>([](R& r, const PassSite& p) { r.add_gather(p.graph, p.env, p.targets); });
        }
    }
    const char* needs_depth_normals() const override { return "RSM"; }
    std::vector<ProgramDesc> programs() const override {
        using S = ShaderStage;
        return {{"rsm", {{S::vertex, "effects/rsm/rsm.vert"}, {S::fragment, "effects/rsm/rsm.frag"}}, {}},
                {"rsm_gather", {{S::vertex, "post/fullscreen.vert"}, {S::fragment, "effects/rsm/gather.frag"}}, {}}};
    }
    std::vector<GpuBlockInfo> gpu_blocks() const override { return {{"RsmData", RSM_BINDING, sizeof(gpu::RsmData), "forward"}}; }
    const char* shading_include() const override { return "effects/rsm/rsm_shading.glsl"; }
    std::vector<ShadingHook> shading_hooks() const override { return {ShadingHook::indirect_light}; }
    std::unique_ptr<EffectRuntime> create_runtime() const override { return std::make_unique<RsmRuntime>(); }
    std::vector<AccuracySweep> accuracy_sweeps(bool quick) const override { return rsm_accuracy_sweeps(quick); }
};

}  // namespace

const Effect& rsm_effect() {
    static const Rsm effect;
    return effect;
}

}  // namespace candela
