#include "render/renderer.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "core/error.hpp"
#include "core/log.hpp"
#include "render/effect_registry.hpp"
#include "render/light_reach.hpp"
#include "render/program_catalog.hpp"

#include <cstring>
#include <map>
#include <set>

#include <glm/gtc/constants.hpp>
#include <glm/gtc/matrix_transform.hpp>

namespace candela {
namespace {
// GGX samples per texel when prefiltering the static environment (once, at start-up).
constexpr int kEnvironmentSamples = 128;
}  // namespace

Renderer::Renderer(const ShaderLibrary& shaders, const Scene& scene, GpuScene& gpu, const RenderSettings& settings,
                   ProgramCache* shared_programs)
    : shaders_(shaders), scene_(scene), gpu_(gpu), scene_bounds_(scene.world_bounds()), ibl_(shaders), own_programs_(shaders),
      programs_(shared_programs ? *shared_programs : own_programs_) {
    material_version_ = gpu.material_version();  // its materials are the ones the first estimate sees
    programs_.get("tonemap");
    frame_ubo_ = gl::Buffer(sizeof(FrameData), nullptr, GL_DYNAMIC_STORAGE_BIT);
    empty_vao_ = gl::VertexArray::create();
    linear_clamp_ = gl::Sampler::create(GL_LINEAR, GL_LINEAR, GL_CLAMP_TO_EDGE, GL_CLAMP_TO_EDGE);
    for (const Effect* e : effect_registry()) {
        effects_.push_back(e->create_runtime());
        effect_ptrs_.push_back(effects_.back().get());
    }
    set_settings(settings);
}

EffectProgress Renderer::effect_progress(std::string_view name) const {
    const auto& reg = effect_registry();
    for (size_t i = 0; i < reg.size() && i < effects_.size(); ++i)
        if (name == reg[i]->name()) return effects_[i]->progress();
    return {};
}

void Renderer::set_settings(const RenderSettings& settings) {
    settings_ = settings;
    if (view_) estimate_if_needed();
    plan();
}

void Renderer::set_view(const Camera& camera, int width, int height) {
    if (view_) return;
    view_ = View{camera, static_cast<float>(width) / static_cast<float>(std::max(height, 1))};
    if (estimate_if_needed()) plan();
}

bool Renderer::estimate_if_needed() {
    // Effects that plan from what the view shows: a tiny trace from the first frame's camera at
    // its aspect, once per renderer and effect.
    if (!view_) return false;
    bool traced = false;
    std::shared_ptr<rt::RtScene> tracer_scene;  // one BVH for all of them
    for (const Effect* e : effects_needing_view_estimate(settings_)) {
        if (estimates_.count(e->name())) continue;
        const ViewEstimate& v = estimates_[e->name()] =
            e->estimate_view({shaders_, scene_, gpu_, view_->camera, view_->aspect, &tracer_scene});
        log::debug(std::string(e->view_estimate(settings_)) + ": " + v.text);
        traced = true;
    }
    return traced;
}

void Renderer::plan() {
    // Plan from the estimates these settings ask for, not every one made so far (an effect whose
    // knob no longer asks for one, gi.threshold=0, plans as a fresh renderer with that knob does);
    // the others stay cached for when a knob asks again.
    ViewEstimates asked;
    for (const Effect* e : effects_needing_view_estimate(settings_))
        if (auto it = estimates_.find(e->name()); it != estimates_.end()) asked.insert(*it);
    const Camera* camera = camera_ ? &*camera_ : nullptr;
    const ViewAmounts amounts = view_amounts({scene_, settings_, camera, &gpu_, aspect_});
    features_ = analyze(scene_, settings_, &asked, camera, &amounts);
    const LightSetup& ls = features_.lights;
    const glm::vec3 viewer = camera ? glm::vec3(camera->world[3]) : glm::vec3(0.0f);
    gpu_.update_lights(ls.area_samples, ls.split_emitters, ls.shadows, ls.cascades, ls.max_shadowed, ls.cutoff, ls.shadow_resolution,
                       ls.shadow_budget_mb, camera ? &viewer : nullptr);
    features_.area_light_pieces = gpu_.light_count() - gpu_.punctual_light_count();
    features_.shadow_budget = ls.shadows ? gpu_.shadow_atlas().text(ls.shadow_budget_mb) : std::string();
    // The static environment map as a prefiltered cube (start-up, and when its size changes).
    if (gpu_.has_environment_map() && env_cube_size_ != settings_.environment.resolution) {
        env_cube_size_ = settings_.environment.resolution;
        env_cube_levels_ = prefiltered_levels(env_cube_size_);
        env_cube_ = ibl_.cube_from_equirect(gpu_.environment_map(), &gpu_.environment_image(), env_cube_size_, kEnvironmentSamples);
        log::debug(std::string("environment cube: ") + (ibl_.last_cube_cached() ? "from the cache" : "computed"));
    }
    for (size_t i = 0; i < effects_.size(); ++i) effects_[i]->configure({scene_, gpu_, settings_, features_, features_.modules[i]});
    // Programs for the planned passes only (built now: a frame never compiles).
    for (const PlannedPass& pass : plan_passes(features_, settings_))
        for (const std::string& program : pass.programs) programs_.get(program);
}

ShaderReload Renderer::reload_shaders(const std::vector<std::filesystem::path>& changed) {
    ShaderReload report = programs_.reload(changed);
    if (!report.rebuilt.empty()) invalidate_captures();  // captured with the old shading
    return report;
}

void Renderer::render(const Camera& view_camera, int width, int height, FrameOutput output, float exposure_ev) {
    // The settings' lens over the camera's own; a lens that turns depth of field on or off re-plans
    // (a changed aperture or focus alone does not: the passes read them every frame).
    aspect_ = static_cast<float>(width) / static_cast<float>(std::max(height, 1));
    set_view(view_camera, width, height);
    const Camera camera = with_lens(view_camera, settings_);
    // Animation: a new pose moves the bounds (shadow fitting, auto focus), the lights
    // and what the probes captured; they re-capture. Motion in view during the shutter plans
    // the motion blur; the renderer re-plans when that turns on or off.
    bool pose_replan = false;
    if (gpu_.material_version() != material_version_) {
        // New materials (a variant chosen live): the view's light is measured again, as a fresh
        // renderer measures it, so that the plan is the one `render --variant` makes.
        material_version_ = gpu_.material_version();
        estimates_.clear();
        if (view_) estimate_if_needed();
    }
    if (gpu_.pose_version() != pose_version_) {
        pose_version_ = gpu_.pose_version();
        scene_bounds_ = scene_.world_bounds();
        invalidate_captures();
        pose_replan = true;  // the light buffer and the effects' set-up (GI's traced geometry, its grid) follow the pose
    }
    // What the effects decide from the view (the lens, what moves in it): a re-plan when one
    // turns on or off (Effect::view_amount).
    const ViewAmounts amounts = view_amounts({scene_, settings_, &view_camera, &gpu_, aspect_});
    bool replan = pose_replan;
    for (const auto& [name, amount] : amounts) replan = replan || (amount > 0.0) != (features_.view_amount(name) > 0.0);
    features_.view_amounts = amounts;
    camera_ = view_camera;
    if (replan) plan();
    if (width != width_ || height != height_) {
        width_ = width;
        height_ = height;
        output_ = gl::Texture::create_2d(GL_RGBA32F, width, height, 1);
        display_ = gl::Texture::create_2d(GL_RGBA8, width, height, 1);
        fbos_.clear();
        pool_.clear();
    }
    // The lights' reach at this view (info's line; the viewer shows it): a few microseconds a
    // light, so every frame, as the camera moves.
    features_.light_reach = features_.punctual_lights > 0
                                ? light_reach(scene_, features_.lights.cutoff,
                                              projection_matrix(view_camera, static_cast<float>(width_) / static_cast<float>(std::max(height_, 1))) *
                                                  glm::inverse(view_camera.world),
                                              width_, height_)
                                      .text()
                                : std::string();
    // The planned effects' sampling: multisampled targets, sub-frames with shifted projections.
    const FrameSampling sampling = frame_sampling(features_, settings_);
    report_ = {};
    timer_.begin_frame();
    for (int sub = 0; sub < sampling.subframes; ++sub) render_subframe(camera, output, exposure_ev, sampling, sub);
}

FrameData Renderer::frame_data(const Camera& camera, const FrameSampling& sampling, int sub) const {
    const int width = width_, height = height_;
    const float aspect = static_cast<float>(width) / static_cast<float>(height);
    FrameData frame{};
    frame.view = glm::inverse(camera.world);
    frame.proj = projection_matrix(camera, aspect);
    if (sampling.subframes > 1) {
        // Shift the image by the sub-frame's offset in pixels (NDC: 2 / size per pixel).
        const glm::vec2 o = sampling.offsets[static_cast<size_t>(sub)];
        frame.proj = glm::translate(glm::mat4(1.0f), glm::vec3(2.0f * o.x / static_cast<float>(width),
                                                               2.0f * o.y / static_cast<float>(height), 0.0f)) *
                     frame.proj;
    }
    frame.view_proj = frame.proj * frame.view;
    frame.inv_view_proj = glm::inverse(frame.view_proj);
    {
        const glm::mat4 ip = glm::inverse(frame.proj);  // column-major: ip[col][row]
        frame.depth_to_view = glm::vec4(ip[2][2], ip[3][2], ip[2][3], ip[3][3]);
    }
    frame.camera_pos = glm::vec4(glm::vec3(camera.world[3]), 1.0f);
    frame.env_radiance = gpu_.environment_radiance();
    frame.env_map_bound = gpu_.has_environment_map() ? 1.0f : 0.0f;
    for (int i = 0; i < 9; ++i) frame.env_sh[i] = glm::vec4(gpu_.environment_sh()[static_cast<size_t>(i)], 0.0f);
    frame.light_count = gpu_.light_count();
    frame.env_mips = gpu_.environment_mips();
    frame.punctual_light_count = gpu_.punctual_light_count();
    frame.debug_view = settings_.debug.view == DebugView::visibility ? DEBUG_VIEW_VISIBILITY
                       : settings_.debug.view == DebugView::ao       ? DEBUG_VIEW_OCCLUSION
                       : settings_.debug.view == DebugView::indirect ? DEBUG_VIEW_INDIRECT
                                                                     : DEBUG_VIEW_NONE;
    frame.debug_light = settings_.debug.light;
    frame.viewport = glm::vec4(static_cast<float>(width), static_cast<float>(height), 1.0f / static_cast<float>(width),
                               1.0f / static_cast<float>(height));
    frame.camera_view = 1;
    frame.specular_filter = sampling.specular_filter_variance;
    frame.env_cube_bound = env_cube_ ? 1 : 0;
    frame.env_mips = env_cube_ ? env_cube_levels_ : 1;
    return frame;
}

int Renderer::declare_passes(FrameGraph& graph, const PassEnv& env, FrameTargets& targets, FrameTargets& post, FrameOutput output,
                             float exposure_ev, bool last) {
    const FrameSampling& sampling = env.sampling;
    const FrameGraph::ResourceId hdr_output = graph.import_texture("hdr", output_, {GL_RGBA32F, env.width, env.height});
    targets.hdr = sampling.resolved ? -1 : hdr_output;
    targets.samples = sampling.resolved ? sampling.samples : 1;
    bool post_started = false;
    for (const auto& e : effects_) e->begin_graph(graph);
    for (const PlannedPass& pass : plan_passes(features_, settings_)) {
        if (pass.post && !post_started) {
            post = targets;
            post.hdr = hdr_output;
            post.samples = 1;
            post.drawn = &targets;
            post_started = true;
        }
        // Sub-frames before the last only draw and accumulate: the post filters see the mean.
        if (pass.post && !last && !pass.every_subframe) continue;
        FrameTargets& t = pass.post ? post : targets;
        // Each planned pass carries its work; an effect's gets the effect's runtime.
        EffectRuntime* runtime = nullptr;
        if (pass.owner) {
            const auto& reg = effect_registry();
            runtime = effects_.at(static_cast<size_t>(std::find(reg.begin(), reg.end(), pass.owner) - reg.begin())).get();
        }
        if (!pass.work) throw Error(ExitCode::internal, "renderer: the pass '" + pass.name + "' was planned without its work");
        pass.work({graph, env, t, runtime});
    }
    // The tonemap pass is always declared; for an HDR-only frame nobody consumes its output and
    // the graph culls it.
    if (!post_started) post = targets;
    add_tonemap_pass(graph, env, post, display_, exposure_ev);
    graph.mark_output(output == FrameOutput::display && last ? post.display : hdr_output);
    // An inspected resource is an output too: it lives to the end, unshared.
    int inspected_id = -1;
    for (size_t i = 0; i < graph.resources().size(); ++i)
        if (!inspect_.empty() && graph.resources()[i].name == inspect_) inspected_id = static_cast<int>(i);
    if (inspected_id >= 0) graph.mark_output(inspected_id);
    return inspected_id;
}

std::string Renderer::execute_graph(FrameGraph& graph, std::map<std::string, double>& sync_ms) {
    // llvmpipe answers the first timer query of a context that covers rasterizer work with its
    // absolute clock (hours): spend that on a throwaway query around a clear.
    if (!timer_warmed_) {
        state_.bind_framebuffer(fbos_.get({&output_}, nullptr));
        gl::Query q = gl::Query::create(GL_TIME_ELAPSED);
        glBeginQuery(GL_TIME_ELAPSED, q.id());
        const float c[4] = {0, 0, 0, 0};
        glClearBufferfv(GL_COLOR, 0, c);
        glEndQuery(GL_TIME_ELAPSED);
        GLuint64 ns = 0;
        glGetQueryObjectui64v(q.id(), GL_QUERY_RESULT, &ns);
        timer_warmed_ = true;
    }
    std::string state_problem;
    std::chrono::steady_clock::time_point pass_start;
    graph.execute(
        state_,
        [&](FrameGraph::PassRecord& p) {
            if (sync_timing_) {
                glFinish();
                pass_start = std::chrono::steady_clock::now();
            }
            timer_.begin(p.name);
        },
        [&](FrameGraph::PassRecord& p) {
            timer_.end();
            if (sync_timing_) {
                glFinish();
                sync_ms[p.name] += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - pass_start).count();
            }
            if (verify_state_ && state_problem.empty()) {
                const std::string bad = state_.verify();
                if (!bad.empty()) state_problem = "pass '" + p.name + "' changed " + bad + " behind the state cache";
            }
        });
    return state_problem;
}

void Renderer::collect_inspectables(const FrameGraph& graph, int inspected_id) {
    inspected_ = nullptr;
    inspectable_.clear();
    for (size_t i = 0; i < graph.resources().size(); ++i) {
        const auto& r = graph.resources()[i];
        if (r.desc.samples > 1) continue;  // the inspector shows 2D textures
        if (r.imported || r.slot >= 0) inspectable_.push_back(r.name);
        if (static_cast<int>(i) == inspected_id) inspected_ = r.imported ? r.imported : &pool_.texture(r.slot);
    }
    std::vector<std::pair<std::string, const gl::Texture*>> owned;
    for (const auto& e : effects_) e->inspectables(owned);
    for (const auto& [name, texture] : owned) {
        inspectable_.push_back(name);
        if (inspect_ == name) inspected_ = texture;
    }
}

void Renderer::record_passes(const FrameGraph& graph, int sub, const std::map<std::string, double>& sync_ms) {
    // Sub-frames after the first add their passes as "name#k" (the GPU timer's order).
    std::string suffix;
    if (sub > 0) suffix.append(1, '#').append(std::to_string(sub + 1));  // (not "#" + ...: GCC 12's -Wrestrict false positive)
    for (const auto& p : graph.passes()) {
        if (p.culled) {
            if (sub == 0) report_.culled.emplace_back(p.name, p.cull_reason);
        } else {
            const auto synced = sync_ms.find(p.name);
            report_.passes.push_back({p.name + suffix, -1.0, p.cpu_ms, p.counters, synced != sync_ms.end() ? synced->second : -1.0});
        }
    }
    report_.pool_allocations = pool_.allocations();
    report_.pool_slots = pool_.size();
}

void Renderer::render_subframe(const Camera& camera, FrameOutput output, float exposure_ev, const FrameSampling& sampling, int sub) {
    const int width = width_, height = height_;
    const bool last = sub + 1 == sampling.subframes;
    const auto t0 = std::chrono::steady_clock::now();
    // The frame's block, completed by the effects (each fills and uploads its own).
    FrameData frame = frame_data(camera, sampling, sub);
    const float aspect = static_cast<float>(width) / static_cast<float>(height);
    for (size_t i = 0; i < effects_.size(); ++i)
        effects_[i]->prepare(
            {settings_, features_, features_.modules[i], gpu_, camera, aspect, scene_bounds_, width, height, frame, effect_ptrs_});
    frame_ubo_.update(0, sizeof(FrameData), &frame);

    // The frame graph: the planned passes, compiled.
    const PassEnv env{gpu_,       settings_,     frame, width,     height,      frame_ubo_, fbos_, programs_,
                      empty_vao_, linear_clamp_, ibl_,  env_cube_, effect_ptrs_, sampling, sub, &light_tiles_};
    FrameGraph graph;
    // `targets`: what the scene is drawn into (FrameSampling::resolved: targets of their own,
    // perhaps multisampled); `post`: the single-sample image the post filters and the tonemap
    // read (render/effect.hpp, Stage::post). The passes keep references to them until they ran.
    FrameTargets targets, post;
    const int inspected_id = declare_passes(graph, env, targets, post, output, exposure_ev, last);
    graph.compile(pool_);
    report_.graph_ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();

    // Run it. The cache cannot know what other code did since the last frame.
    state_.reset();
    const int calls_before = state_.real_calls(), skipped_before = state_.skipped_calls();
    std::map<std::string, double> sync_ms;
    const std::string state_problem = execute_graph(graph, sync_ms);
    collect_inspectables(graph, inspected_id);
    graph.release(pool_);
    // Leave GL as other code (ImGui, readback) expects it.
    state_.apply(gl::PipelineState{.depth_test = false, .depth_func = GL_LESS, .reversed_z = false});
    state_.bind_framebuffer(0);

    record_passes(graph, sub, sync_ms);
    report_.state_calls += state_.real_calls() - calls_before;
    report_.state_calls_skipped += state_.skipped_calls() - skipped_before;
    if (!state_problem.empty()) throw Error(ExitCode::internal, state_problem);
}

void Renderer::resolve_gpu_times() {
    const auto& results = timer_.resolve_current();
    for (size_t i = 0; i < report_.passes.size() && i < results.size(); ++i) report_.passes[i].gpu_ms = results[i].second;
}

std::vector<std::uint8_t> Renderer::read_display() const {
    std::vector<std::uint8_t> bytes(static_cast<size_t>(width_) * static_cast<size_t>(height_) * 4);
    glGetTextureImage(display_.id(), 0, GL_RGBA, GL_UNSIGNED_BYTE, static_cast<GLsizei>(bytes.size()), bytes.data());
    const size_t row = static_cast<size_t>(width_) * 4;
    for (int y = 0; y < height_ / 2; ++y)
        std::swap_ranges(bytes.begin() + static_cast<std::ptrdiff_t>(static_cast<size_t>(y) * row),
                         bytes.begin() + static_cast<std::ptrdiff_t>(static_cast<size_t>(y + 1) * row),
                         bytes.begin() + static_cast<std::ptrdiff_t>(static_cast<size_t>(height_ - 1 - y) * row));
    return bytes;
}

ImageF Renderer::read_radiance() const {
    ImageF img(width_, height_, 4);
    glGetTextureImage(output_.id(), 0, GL_RGBA, GL_FLOAT, static_cast<GLsizei>(img.pixels.size() * sizeof(float)),
                      img.pixels.data());
    // GL's first row is the bottom one.
    const size_t row = static_cast<size_t>(width_) * 4;
    for (int y = 0; y < height_ / 2; ++y)
        std::swap_ranges(img.pixels.begin() + static_cast<std::ptrdiff_t>(static_cast<size_t>(y) * row),
                         img.pixels.begin() + static_cast<std::ptrdiff_t>(static_cast<size_t>(y + 1) * row),
                         img.pixels.begin() + static_cast<std::ptrdiff_t>(static_cast<size_t>(height_ - 1 - y) * row));
    return img;
}

}  // namespace candela
