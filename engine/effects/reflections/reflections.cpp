#include "effects/reflections/reflections.hpp"

#include <algorithm>
#include <cstdio>
#include <cstring>

#include <glm/gtc/constants.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "core/log.hpp"
#include "effects/reflections/reflections_data.h"
#include "effects/reflections/reflections_sweep.hpp"
#include "gpu/bindings.h"
#include "render/environment.hpp"
#include "render/features.hpp"
#include "render/passes/pass_env.hpp"

namespace candela {

const std::vector<ProbePlacement>& ReflectionsRuntime::placements() const { return res_.placements; }

void ReflectionsRuntime::configure(const EffectSetup& s) {
    // Probes are planned now and again by the next frame (automatic ones rank by what that
    // frame's view shows), and captured by the next frame that plans env_probe.
    options_ = s.settings.get<ReflectionsOptions>();
    res_.valid = false;
    res_.placements.clear();
    scene_bounds_ = s.scene.world_bounds();
    placed_ = false;
    summary_.clear();
    scene_ = s.decision.planned ? &s.scene : nullptr;
    gpu_ = &s.gpu;
    // A plan without a view (reflectance alone ranks the probes) until the first frame's.
    if (scene_) res_.placements = place_probes(s.scene, s.gpu.draws(), options_, nullptr, &summary_);
}

void ReflectionsRuntime::place(const FramePrep& p) {
    placed_ = true;
    if (!scene_) return;
    const glm::mat4 view_proj = p.frame.view_proj;
    res_.placements = place_probes(*scene_, gpu_->draws(), options_, &view_proj, &summary_);
    res_.cubes = 0;  // prepare_faces uploads this plan's probes
    log::info(scene_->source.filename().string() + ": reflection probes: " + summary_);
    for (size_t k = 0; k < res_.placements.size(); ++k) {
        const ProbePlacement& pl = res_.placements[k];
        char line[160];
        std::snprintf(line, sizeof line, "  probe %zu at (%.3g, %.3g, %.3g) radius %.3g weight %.3g: ", k, pl.position.x, pl.position.y,
                      pl.position.z, pl.has_box ? 0.0 : static_cast<double>(pl.radius), static_cast<double>(pl.weight));
        log::debug(line + pl.origin);
    }
}

void ReflectionsRuntime::prepare(const FramePrep& p) {
    options_ = p.settings.get<ReflectionsOptions>();
    if (!placed_) place(p);
    probes_id_ = -1;
    on_ = p.decision.planned && !res_.placements.empty();
    gpu::ReflectionsData d{};
    d.refraction = p.decision.planned ? 1 : 0;  // transmissive surfaces refract through the probes
    if (on_) {
        d.probes = static_cast<int>(res_.placements.size());
        d.levels = prefiltered_levels(options_.probe_resolution);
        d.parallax = options_.parallax ? 1 : 0;
    }
    if (!block_) {
        block_ = gl::Buffer(sizeof d, nullptr, GL_DYNAMIC_STORAGE_BIT);
        capture_block_ = gl::Buffer(sizeof d, nullptr, GL_DYNAMIC_STORAGE_BIT);
    }
    block_.update(0, sizeof d, &d);
    // The defines follow block_, the block the lighting passes bind. The probe capture binds
    // capture_block_ instead and draws with the unspecialised forward program.
    defines_.clear();
    if (d.refraction == 0) defines_.push_back("REFLECTIONS_NO_REFRACTION");
    if (d.probes <= 0) defines_.push_back("REFLECTIONS_NO_PROBES");
    gpu::ReflectionsData capture = d;
    capture.probes = 0;  // shading inside a probe reads the static environment
    capture.capture = 1;
    capture_block_.update(0, sizeof capture, &capture);
    if (on_) prepare_faces(p);
}

void ReflectionsRuntime::prepare_faces(const FramePrep& prep) {
    const Bounds& scene_bounds = scene_bounds_;

        Resources& pr = res_;
        const int size = options_.probe_resolution;
        const int cubes = static_cast<int>(pr.placements.size());
        if (pr.size != size || pr.cubes != cubes) {
            pr.levels = prefiltered_levels(size);
            pr.capture = ImageBasedLighting::create_cube_array(size, cubes, 0);
            pr.filtered = ImageBasedLighting::create_cube_array(size, cubes, pr.levels);
            pr.depth = gl::Texture::create_2d(GL_DEPTH_COMPONENT32F, size, size, 1);
            {
                GLuint id = 0;
                glCreateTextures(GL_TEXTURE_CUBE_MAP_ARRAY, 1, &id);
                glTextureStorage3D(id, 1, GL_R32F, size, size, 6 * cubes);
                // Nearest: a linear blend across a silhouette would invent a surface between.
                glTextureParameteri(id, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
                glTextureParameteri(id, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
                glTextureParameteri(id, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
                glTextureParameteri(id, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
                pr.distance = gl::Texture::adopt(id, size, size, GL_R32F);
            }
            pr.face_fbos.clear();
            for (int layer = 0; layer < 6 * cubes; ++layer) {
                gl::Framebuffer fbo = gl::Framebuffer::create();
                glNamedFramebufferTextureLayer(fbo.id(), GL_COLOR_ATTACHMENT0, pr.capture.id(), 0, layer);
                fbo.attach(GL_DEPTH_ATTACHMENT, pr.depth);
                glNamedFramebufferDrawBuffer(fbo.id(), GL_COLOR_ATTACHMENT0);
                fbo.check_complete("reflection probe face");
                pr.face_fbos.push_back(std::move(fbo));
            }
            std::vector<ProbeData> data;
            for (const ProbePlacement& p : pr.placements) data.push_back(to_gpu(p));
            pr.data = gl::Buffer(static_cast<GLsizeiptr>(data.size() * sizeof(ProbeData)), data.data(), 0);
            pr.size = size;
            pr.cubes = cubes;
            pr.valid = false;
        }
        pr.sky = prep.features.environment;
        if (pr.valid && options_.update == ProbeUpdate::once) return;
        // One frame per face: a 90-degree camera at the probe looking along the face's axis, with the
        // up vectors of GL's cube-map face orientation (so face images need no flipping).
        static const glm::vec3 forward[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
        static const glm::vec3 up[6] = {{0, -1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}, {0, -1, 0}, {0, -1, 0}};
        GLint align = 256;
        glGetIntegerv(GL_UNIFORM_BUFFER_OFFSET_ALIGNMENT, &align);
        pr.frame_stride = (static_cast<GLsizeiptr>(sizeof(FrameData)) + align - 1) / align * align;
        std::vector<std::uint8_t> bytes(static_cast<size_t>(pr.frame_stride) * static_cast<size_t>(6 * cubes));
        pr.face_view_proj.assign(static_cast<size_t>(6 * cubes), glm::mat4(1.0f));
        Camera cam;
        cam.yfov = glm::half_pi<float>();
        cam.aspect_ratio = 1.0f;
        // Near plane: a small fraction of the scene, so that nearby walls are not clipped.
        cam.znear = std::max(1e-4f, 1e-3f * glm::length(scene_bounds.extent()));
        pr.znear = cam.znear;
        for (int k = 0; k < cubes; ++k) {
            const glm::vec3 p = pr.placements[static_cast<size_t>(k)].position;
            for (int face = 0; face < 6; ++face) {
                FrameData f = prep.frame;
                f.view = glm::lookAt(p, p + forward[face], up[face]);
                f.proj = projection_matrix(cam, 1.0f);
                f.view_proj = f.proj * f.view;
                f.inv_view_proj = glm::inverse(f.view_proj);
                const glm::mat4 ip = glm::inverse(f.proj);
                f.depth_to_view = glm::vec4(ip[2][2], ip[3][2], ip[2][3], ip[3][3]);
                f.camera_pos = glm::vec4(p, 1.0f);
                f.viewport = glm::vec4(static_cast<float>(size), static_cast<float>(size), 1.0f / static_cast<float>(size),
                                       1.0f / static_cast<float>(size));
                f.camera_view = 0;  // no screen-space effect buffers in a probe's faces
                f.debug_view = 0;
                f.debug_light = 0;
                f.specular_filter = 0.0f;  // a face's texel is its centre's value (filtered later)
                std::memcpy(bytes.data() + pr.frame_stride * (6 * k + face), &f, sizeof(FrameData));
                pr.face_view_proj[static_cast<size_t>(6 * k + face)] = f.view_proj;
            }
        }
        const auto total = static_cast<GLsizeiptr>(bytes.size());
        if (!pr.frames || pr.frames.size() != total) pr.frames = gl::Buffer(total, nullptr, GL_DYNAMIC_STORAGE_BIT);
        pr.frames.update(0, total, bytes.data());
}

void ReflectionsRuntime::begin_graph(FrameGraph& graph) {
    if (on_) probes_id_ = graph.import_texture("probes", res_.filtered, {GL_RGBA32F, res_.size, res_.size});
}

void ReflectionsRuntime::add_probes(FrameGraph& graph, const PassEnv& env) {
    // probe.update=once: captured by an earlier frame of the same scene and settings.
    if (on_ && (!res_.valid || options_.update == ProbeUpdate::every_frame)) add_capture(graph, env);
}

void ReflectionsRuntime::read_shading_inputs(FrameGraph::Builder& b) const {
    if (probes_id_ >= 0) b.read(probes_id_);
}

void ReflectionsRuntime::bind_shading_inputs(const PassEnv&, FrameGraph::Context*) const {
    glBindBufferBase(GL_UNIFORM_BUFFER, REFLECTIONS_BINDING, block_.id());
    if (on_) {
        gl::bind_texture_unit(REFLECTIONS_PROBES_UNIT, res_.filtered);
        gl::bind_texture_unit(REFLECTIONS_DISTANCE_UNIT, res_.distance);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, REFLECTIONS_PROBES_BINDING, res_.data.id());
    }
}

void ReflectionsRuntime::inspectables(std::vector<std::pair<std::string, const gl::Texture*>>& out) const {
    if (res_.filtered) out.emplace_back("probe_cube", &res_.filtered);
}

namespace {

// Whether a world box lies entirely beyond one clip plane of view_proj (reversed Z: z > w is in
// front of the near plane, w <= 0 behind the eye).
bool outside_frustum(const Bounds& b, const glm::mat4& view_proj) {
    int outside[6] = {0, 0, 0, 0, 0, 0};
    for (int c = 0; c < 8; ++c) {
        const glm::vec4 p = view_proj * glm::vec4(c & 1 ? b.max.x : b.min.x, c & 2 ? b.max.y : b.min.y, c & 4 ? b.max.z : b.min.z, 1.0f);
        outside[0] += p.x < -p.w, outside[1] += p.x > p.w, outside[2] += p.y < -p.w, outside[3] += p.y > p.w;
        outside[4] += p.z > p.w, outside[5] += p.w <= 0.0f;
    }
    for (int k = 0; k < 6; ++k)
        if (outside[k] == 8) return true;
    return false;
}

}  // namespace

// Reflection probes: each probe's six cube faces rendered with the forward path from its
// position (opaque and masked geometry, then the sky), then GGX-prefiltered for rough
// reflections. Draws whose bounds contain the probe are left out (from inside they would only
// hide the room); the other objects a shared probe serves are captured, as they see each other. Blended draws are left out too (no per-face sorting). Inside a
// probe, shading reads the static environment, not the probes (no feedback between probes),
// and no SSAO/RSM. Per face, only the draws in its frustum are drawn. (A depth-only pass
// first, then shading with depth EQUAL, was measured slower: llvmpipe runs most of the forward
// program in the depth pass too, and the captures have little overdraw.)
void ReflectionsRuntime::add_capture(FrameGraph& graph, const PassEnv& env) {
    graph.add_pass(
        "env_probe",
        [&](FrameGraph::Builder& b) {
            read_lighting_inputs(b, env);
            b.write(probes_id_);
        },
        [this, &env](FrameGraph::Context& ctx) {
                Resources& pr = res_;
                bind_scene_buffers(env);
                // Inside a probe, shading reads the static environment, not the probes.
                glBindBufferBase(GL_UNIFORM_BUFFER, REFLECTIONS_BINDING, capture_block_.id());
                const auto& draws = env.scene.draws();
                const GLuint forward = env.programs.get("forward").id();
                const GLuint distance = env.programs.get("probe_distance").id();
                std::vector<size_t> visible;
                for (int k = 0; k < pr.cubes; ++k) {
                    const ProbePlacement& placement = pr.placements[static_cast<size_t>(k)];
                    std::vector<bool> skip(draws.size(), false);
                    for (int i : placement.excluded_draws) skip[static_cast<size_t>(i)] = true;
                    for (int face = 0; face < 6; ++face) {
                        const int layer = 6 * k + face;
                        visible.clear();
                        for (size_t i = 0; i < draws.size(); ++i)
                            if (!skip[i] && draws[i].alpha_mode != AlphaMode::blend &&
                                !outside_frustum(draws[i].world_bounds, pr.face_view_proj[static_cast<size_t>(layer)]))
                                visible.push_back(i);
                        glBindBufferRange(GL_UNIFORM_BUFFER, FRAME_BINDING, pr.frames.id(), pr.frame_stride * layer, sizeof(FrameData));
                        gl::PipelineState ps;
                        ps.depth_test = true;
                        ps.depth_func = GL_GREATER;
                        ps.depth_write = true;
                        ctx.state.apply(ps);
                        ctx.state.bind_framebuffer(pr.face_fbos[static_cast<size_t>(layer)].id());
                        ctx.state.viewport(0, 0, pr.size, pr.size);
                        const float clear_color[4] = {0, 0, 0, 0};
                        glClearBufferfv(GL_COLOR, 0, clear_color);
                        const float clear_depth = 0.0f;
                        glClearBufferfv(GL_DEPTH, 0, &clear_depth);
                        ctx.state.use_program(forward);
                        ctx.state.bind_vertex_array(env.scene.vertex_array().id());
                        for (size_t i : visible) draw_item(env, ctx, draws[i], !draws[i].double_sided, GL_BACK);
                        if (pr.sky) {
                            // The sky's alpha stays the clear value 0: it adds no area light.
                            glColorMaski(0, GL_TRUE, GL_TRUE, GL_TRUE, GL_FALSE);
                            gl::PipelineState sky;
                            sky.depth_test = true;
                            sky.depth_func = GL_GEQUAL;
                            sky.depth_write = false;
                            ctx.state.apply(sky);
                            ctx.state.use_program(env.programs.get("sky").id());
                            ctx.state.bind_vertex_array(env.empty_vao.id());
                            glDrawArrays(GL_TRIANGLES, 0, 3);
                            glColorMaski(0, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
                            ++ctx.counters.draw_calls;
                            ++ctx.counters.triangles;
                        }
                        // The face's distances, before the next face reuses the depth buffer.
                        ctx.state.use_program(distance);
                        gl::bind_texture_unit(REFLECTIONS_FACE_DEPTH_UNIT, pr.depth);
                        glBindImageTexture(REFLECTIONS_DISTANCE_IMAGE, pr.distance.id(), 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_R32F);
                        glProgramUniform1i(distance, 0, layer);
                        glProgramUniform1f(distance, 1, pr.znear);
                        glDispatchCompute(static_cast<GLuint>((pr.size + 7) / 8), static_cast<GLuint>((pr.size + 7) / 8), 1);
                        ++ctx.counters.dispatches;
                        glBindTextureUnit(REFLECTIONS_FACE_DEPTH_UNIT, 0);
                    }
                }
                glBindBufferBase(GL_UNIFORM_BUFFER, FRAME_BINDING, env.frame_ubo.id());
                glBindImageTexture(REFLECTIONS_DISTANCE_IMAGE, 0, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
                glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
                glTextureBarrier();
                env.ibl.float_mipmaps().generate(pr.capture, GL_TEXTURE_CUBE_MAP_ARRAY, pr.size, pr.size, 6 * pr.cubes, 0);
                env.ibl.prefilter(pr.capture, pr.filtered, pr.size, pr.levels, pr.cubes, options_.probe_samples);
                ctx.counters.dispatches += pr.levels;
                // The prefilter changed programs and image bindings behind the state cache.
                ctx.state.reset();
                pr.valid = true;
        });
}

// Deferred path: transmissive surfaces, already in the G-buffer (for depth, SSAO and lighting of
// what is behind nothing), are shaded again with the forward program, which refracts through
// the probes; the depth test EQUAL keeps exactly the visible fragments.
void ReflectionsRuntime::add_transmissive(FrameGraph& graph, const PassEnv& env, FrameTargets& targets) {
    graph.add_pass(
        "transmissive",
        [&](FrameGraph::Builder& b) {
            b.read(targets.depth);
            read_lighting_inputs(b, env);
            b.write(targets.hdr);
        },
            [&env, &targets](FrameGraph::Context& ctx) {
                gl::PipelineState ps;
                ps.depth_test = true;
                ps.depth_func = GL_EQUAL;
                ps.depth_write = false;
                begin_forward_shading(env, ctx, targets, ps);
                ctx.state.bind_vertex_array(env.scene.vertex_array().id());
                const Scene& scene = env.scene.scene();
                for (const auto& d : env.scene.draws())
                    if (d.alpha_mode != AlphaMode::blend && scene.material(d.primitive_material).transmission > 0.0f)
                        draw_item(env, ctx, d, !d.double_sided, GL_BACK);
            });
}

namespace {

class Reflections final : public Effect {
public:
    const char* name() const override { return "reflections"; }
    std::any default_options() const override { return ReflectionsOptions{}; }
    std::vector<Knob> knobs() const override {
        auto access = [](RenderSettings& s) -> ReflectionsOptions& { return s.get<ReflectionsOptions>(); };
        std::vector<Knob> rows =
            KnobRows<ReflectionsOptions>("reflections", access)
                .real("max_roughness", &ReflectionsOptions::max_roughness, 0.0f, 1.0f,
                      "metallic materials rougher than this call for no reflections")
                .rows;
        std::vector<Knob> probe =
            KnobRows<ReflectionsOptions>("probe", access)
                .integer("resolution", &ReflectionsOptions::probe_resolution, 16, 1024, "face size of each reflection probe's cube map")
                .choice("update", &ReflectionsOptions::update, kProbeUpdates,
                        "once: capture when the scene or the settings change; every_frame: every frame")
                .choice("placement", &ReflectionsOptions::placement, kProbePlacements,
                        "scene: the extras.reflection_probe nodes (auto if there are none); auto: probes planned for the "
                        "reflective objects (objects with nearly the same surroundings share one), no box")
                .integer("budget", &ReflectionsOptions::probe_budget, 1, 64,
                         "at most this many automatic probes: beyond it, the probes that show least (screen coverage x "
                         "reflectance) merge into others")
                .real("merge", &ReflectionsOptions::probe_merge, 0.0f, 4.0f,
                      "objects share an automatic probe while its parallax error (offset / distance to other geometry) "
                      "stays below this")
                .integer("samples", &ReflectionsOptions::probe_samples, 1, 1024,
                         "GGX samples per texel when prefiltering probes for rough reflections")
                .boolean("parallax", &ReflectionsOptions::parallax,
                         "lookups of probes without a box find where the ray meets what the probe saw (its distance cube); "
                         "off: an infinitely distant lookup")
                .rows;
        rows.insert(rows.end(), probe.begin(), probe.end());
        return rows;
    }
    std::vector<std::string> knob_groups() const override { return {"reflections", "probe"}; }
    EffectDecision decide(const Features& f, const RenderSettings& s) const override {
        const Feature need = analyze_features(*f.source, s.get<ReflectionsOptions>().max_roughness).reflections;
        return decide_effect(name(), s.on(name()), need.needed, need.reason, s.gating);
    }
    void plan(Stage stage, const Features& f, const RenderSettings& s, std::vector<PlannedPass>& out) const override {
        const ReflectionsOptions& o = s.get<ReflectionsOptions>();
        if (stage == Stage::light_views)
            out.push_back({"env_probe",
                           f.decision(name()).reason.substr(4) + "; probe.update=" + choice_name(kProbeUpdates, o.update) +
                               (o.update == ProbeUpdate::once ? " (captured when the scene or settings change)" : ""),
                           this, f.environment ? std::vector<std::string>{"forward", "sky", "probe_distance"}
                                               : std::vector<std::string>{"forward", "probe_distance"}});
        using R = ReflectionsRuntime;
        if (stage == Stage::light_views) out.back().work = runtime_pass<R>([](R& r, const PassSite& p) { r.add_probes(p.graph, p.env); });
        if (stage == Stage::after_lighting && f.deferred && f.scene.transmission.needed) {
            out.push_back({"transmissive", "transmissive surfaces refract through the probes (forward shading, depth EQUAL)", this,
                           {"forward"}});
            out.back().work = runtime_pass<R>([](R& r, const PassSite& p) { r.add_transmissive(p.graph, p.env, p.targets); });
        }
    }
    std::vector<ProgramDesc> programs() const override {
        return {{"probe_distance", {{ShaderStage::compute, "effects/reflections/probe_distance.comp"}}, {}}};
    }
    std::vector<GpuBlockInfo> gpu_blocks() const override {
        return {{"ReflectionsData", REFLECTIONS_BINDING, sizeof(gpu::ReflectionsData), "forward"}};
    }
    const char* shading_include() const override { return "effects/reflections/reflections_shading.glsl"; }
    std::vector<ShadingHook> shading_hooks() const override { return {ShadingHook::reflection_source, ShadingHook::reflection_radiance, ShadingHook::refraction, ShadingHook::capture_view}; }
    std::unique_ptr<EffectRuntime> create_runtime() const override { return std::make_unique<ReflectionsRuntime>(); }
    std::vector<AccuracySweep> accuracy_sweeps(bool quick) const override { return reflections_accuracy_sweeps(quick); }
    // The probes as the first frame from this view places them.
    std::vector<std::string> info_lines(const Scene& scene, const RenderSettings& s, const glm::mat4& view_proj) const override {
        std::string summary;
        place_probes(scene, {}, s.get<ReflectionsOptions>(), &view_proj, &summary);
        return {"reflection probes: " + summary};
    }
};

}  // namespace

const Effect& reflections_effect() {
    static const Reflections effect;
    return effect;
}

}  // namespace candela
