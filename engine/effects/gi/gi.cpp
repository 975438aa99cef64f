// GI probes (gi.hpp). The pass "gi_probes" (light_views stage) runs the update iterations a frame
// owes: per batch of probes, probe_trace.comp (the rays, with the tracer's BVH and light sampling)
// then probe_update.comp (irradiance and distance atlases). A still converges before its
// frame (gi.budget = 0); the viewer spends gi.budget rays per frame until the probes have done
// gi.iterations updates. The shading reads the atlases through gi_shading.glsl.
#include "effects/gi/gi.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <memory>

#include <glm/gtc/quaternion.hpp>
#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "effects/gi/estimate.hpp"
#include "effects/gi/gi_data.h"
#include "effects/gi/gi_sweep.hpp"
#include "gpu/bindings.h"
#include "render/features.hpp"
#include "render/passes/pass_env.hpp"
#include "rt/ray_tracer.hpp"

namespace candela {
namespace {

constexpr int kIrradianceTexels = 8;  // interior texels per side of a probe's irradiance map
constexpr int kDepthTexels = 12;      // of its distance map

int rounded_rays(int rays) { return std::max(64, (rays + 63) / 64 * 64); }

// A uniformly random rotation (Shoemake 1992, "Uniform random rotations", Graphics Gems III) from
// a deterministic hash of the iteration, so that renders are reproducible.
glm::mat4 random_rotation(std::uint32_t iteration, std::uint32_t seed) {
    auto hash = [](std::uint32_t v) {
        v = v * 747796405u + 2891336453u;
        std::uint32_t w = ((v >> ((v >> 28u) + 4u)) ^ v) * 277803737u;
        return (w >> 22u) ^ w;
    };
    const std::uint32_t h1 = hash(iteration * 3u + seed * 7919u), h2 = hash(h1 ^ 0x9e3779b9u), h3 = hash(h2 ^ 0x85ebca6bu);
    const double u1 = h1 / 4294967296.0, u2 = h2 / 4294967296.0, u3 = h3 / 4294967296.0;
    const double a = std::sqrt(1.0 - u1), b = std::sqrt(u1);
    const double t1 = 2.0 * 3.14159265358979 * u2, t2 = 2.0 * 3.14159265358979 * u3;
    const glm::quat q(static_cast<float>(b * std::cos(t2)), static_cast<float>(a * std::sin(t1)),
                      static_cast<float>(a * std::cos(t1)), static_cast<float>(b * std::sin(t2)));
    return glm::mat4_cast(glm::normalize(q));
}

class GiRuntime final : public EffectRuntime, public GiStatusView {
public:
    void configure(const EffectSetup& s) override {
        on_ = s.decision.planned;
        if (!on_) return;
        options_ = s.settings.get<GiOptions>();
        const IndirectEstimate* estimate = indirect_estimate(s.features);
        const int bounces = gi_planned_bounces(options_, estimate);
        const int probes = gi_planned_probes(options_, estimate);
        if (scene_ != &s.scene || !rt_scene_) {
            scene_ = &s.scene;
            rt_scene_ = std::make_unique<rt::RtScene>(s.scene, static_cast<int>(s.scene.materials.size()));
            pose_version_ = s.gpu.pose_version();
            reset_ = true;
        } else if (pose_version_ != s.gpu.pose_version()) {
            // Animation: the probes trace the posed geometry; they start over.
            rt_scene_->update(s.scene, rt::RtUpdate::rebuild);
            pose_version_ = s.gpu.pose_version();
            reset_ = true;
        }
        frame_block_ = rt::scene_frame_block(s.scene, *rt_scene_, s.gpu);
        // The grid: cell-centred in the scene's bounds, `probes` along the longest axis.
        const Bounds b = s.scene.world_bounds();
        const glm::vec3 extent = b.empty() ? glm::vec3(1.0f) : glm::max(b.extent(), glm::vec3(0.0f));
        const float longest = std::max({extent.x, extent.y, extent.z, 1e-30f});
        glm::ivec3 counts;
        glm::vec3 spacing, origin;
        for (int a = 0; a < 3; ++a) {
            counts[a] = std::clamp(static_cast<int>(std::lround(probes * extent[a] / longest)), 1, probes);
            // The outer probes sit gi.inset of a cell from the bounds (0.5: cell centres).
            const float cell = extent[a] > 0.0f ? extent[a] / static_cast<float>(counts[a]) : longest / static_cast<float>(probes);
            const float inset = counts[a] > 1 ? options_.inset * cell : 0.5f * extent[a];
            spacing[a] = counts[a] > 1 ? (extent[a] - 2.0f * inset) / static_cast<float>(counts[a] - 1) : cell;
            origin[a] = (b.empty() ? 0.0f : b.min[a]) + inset;
        }
        const int rays = rounded_rays(options_.rays);
        const int iterations = bounces + options_.iterations;
        if (counts != counts_ || spacing != spacing_ || origin != origin_ || rays != rays_ || bounces != bounces_ ||
            iterations != iterations_ || options_.bias != bias_ || options_.inset != inset_)
            reset_ = true;
        counts_ = counts, spacing_ = spacing, origin_ = origin, rays_ = rays, bounces_ = bounces;
        iterations_ = iterations, bias_ = options_.bias, inset_ = options_.inset;
        const float min_spacing = std::min({spacing.x, spacing.y, spacing.z});
        max_distance_ = 1.5f * glm::length(spacing * glm::vec3(counts));
        shading_bias_ = options_.bias * 0.75f * min_spacing;
        if (reset_) allocate();
    }

    void invalidate() override { reset_ = true; }

    void prepare(const FramePrep& p) override {
        on_ = p.decision.planned;
        if (!block_) {
            block_ = gl::Buffer(sizeof(gpu::GiData), nullptr, GL_DYNAMIC_STORAGE_BIT);
            sampler_ = gl::Sampler::create(GL_LINEAR, GL_LINEAR, GL_CLAMP_TO_EDGE, GL_CLAMP_TO_EDGE);
        }
        if (on_ && reset_) allocate();
        upload(shading_block());
    }

    void begin_graph(FrameGraph& graph) override {
        irr_id_ = depth_id_ = -1;
        if (!on_) return;
        irr_id_ = graph.import_texture("gi_irradiance", irradiance_, {GL_RGBA32F, irradiance_.width(), irradiance_.height()});
        depth_id_ = graph.import_texture("gi_depth", depth_, {GL_RG32F, depth_.width(), depth_.height()});
    }

    // The pass gi_probes: this frame's share of the probes' relocation and updates.
    void add_probes(FrameGraph& graph, const PassEnv& env) {
        graph.add_pass(
            "gi_probes",
            [&](FrameGraph::Builder& b) {
                b.write(irr_id_);
                b.write(depth_id_);
            },
            [this, &env](FrameGraph::Context& ctx) { update(env, ctx); });
    }

    void read_shading_inputs(FrameGraph::Builder& b) const override {
        if (irr_id_ >= 0) b.read(irr_id_);
        if (depth_id_ >= 0) b.read(depth_id_);
    }

    std::vector<std::string> shading_defines() const override { return defines_; }

    void bind_shading_inputs(const PassEnv& /*env*/, FrameGraph::Context* /*ctx*/) const override {
        glBindBufferBase(GL_UNIFORM_BUFFER, GI_BINDING, block_.id());
        if (on_ && irradiance_) {
            glBindTextureUnit(GI_IRRADIANCE_UNIT, irradiance_.id());
            glBindSampler(GI_IRRADIANCE_UNIT, sampler_.id());
            glBindTextureUnit(GI_DEPTH_UNIT, depth_.id());
            glBindSampler(GI_DEPTH_UNIT, sampler_.id());
            glBindTextureUnit(GI_OFFSETS_UNIT, offsets_.id());
            glBindSampler(GI_OFFSETS_UNIT, sampler_.id());
        }
    }

    void inspectables(std::vector<std::pair<std::string, const gl::Texture*>>& out) const override {
        if (irradiance_) out.emplace_back("gi_irradiance", &irradiance_);
        if (depth_) out.emplace_back("gi_depth", &depth_);
    }

    GiStatus gi_status() const override {
        GiStatus st;
        st.planned = on_;
        st.counts = counts_;
        st.rays = rays_;
        st.bounces = bounces_;
        st.updates_done = iteration_;
        st.updates_planned = iterations_;
        st.rays_last_frame = rays_last_frame_;
        st.nonfinite = nonfinite_;
        return st;
    }

    EffectProgress progress() const override {
        const GiStatus st = gi_status();
        EffectProgress p;
        p.active = st.planned;
        p.converged = st.converged();
        p.steps_done = st.updates_done;
        p.work_last_frame = st.rays_last_frame;
        p.line = gi_status_line(st, options_.budget);
        p.pace = "gi.budget " + std::to_string(options_.budget) + " rays/frame";
        return p;
    }

    int probe_count() const { return counts_.x * counts_.y * counts_.z; }

private:
    void allocate() {
        reset_ = false;
        iteration_ = 0;
        cursor_ = 0;
        const int tiles_x = counts_.x * counts_.z, tiles_y = counts_.y;
        irradiance_ = gl::Texture::create_2d(GL_RGBA32F, tiles_x * (kIrradianceTexels + 2), tiles_y * (kIrradianceTexels + 2), 1);
        depth_ = gl::Texture::create_2d(GL_RG32F, tiles_x * (kDepthTexels + 2), tiles_y * (kDepthTexels + 2), 1);
        const float zero[4] = {0, 0, 0, 0};
        glClearTexImage(irradiance_.id(), 0, GL_RGBA, GL_FLOAT, zero);
        glClearTexImage(depth_.id(), 0, GL_RG, GL_FLOAT, zero);
        offsets_ = gl::Texture::create_2d(GL_RGBA32F, tiles_x, tiles_y, 1);
        glClearTexImage(offsets_.id(), 0, GL_RGBA, GL_FLOAT, zero);
        relocation_rounds_ = 0;
        rays_buffer_ = gl::Buffer(static_cast<GLsizeiptr>(probe_count()) * rays_ * 32, nullptr, GL_DYNAMIC_STORAGE_BIT);
        GLuint view = 0;
        glCreateTextures(GL_TEXTURE_BUFFER, 1, &view);
        glTextureBuffer(view, GL_RGBA32F, rays_buffer_.id());
        rays_view_ = gl::Texture::adopt(view, probe_count() * rays_ * 2, 1, GL_RGBA32F);
        const unsigned zeros[4] = {0, 0, 0, 0};
        diagnostics_ = gl::Buffer(sizeof zeros, zeros, GL_DYNAMIC_STORAGE_BIT);
        nonfinite_ = 0;
    }

    gpu::GiData shading_block() const {
        gpu::GiData d{};
        d.origin = origin_;
        d.on = on_ && iteration_ > 0 ? 1.0f : 0.0f;
        d.spacing = spacing_;
        d.shading_bias = shading_bias_;
        d.probe_counts = counts_;
        d.irradiance_texels = kIrradianceTexels;
        d.depth_texels = kDepthTexels;
        d.rays_per_probe = rays_;
        d.iteration = iteration_;
        d.first_probe = 0;
        d.weight = 1.0f;
        d.miss_distance = max_distance_;
        d.seed = 0.0f;
        d.depth_sharpness = 50.0f;
        d.rotation = glm::mat4(1.0f);
        return d;
    }

    // Every upload goes to the block the shading binds (the trace reads it too): the defines
    // follow it, so that a lighting pass always gets the variant of what it will read.
    void upload(const gpu::GiData& d) {
        block_.update(0, sizeof d, &d);
        defines_.clear();
        if (d.on < 0.5f) defines_.push_back("GI_OFF");  // no probe data to read yet
    }

    // The weight of iteration k's estimate: the first `bounces_` replace (each adds a bounce),
    // the rest average (a running mean from the last replacing iteration on).
    float weight(int k) const { return k < bounces_ ? 1.0f : 1.0f / static_cast<float>(k - bounces_ + 2); }

    void update(const PassEnv& env, FrameGraph::Context& ctx) {
        rays_last_frame_ = 0;
        if (options_.restart) iteration_ = cursor_ = 0;  // update 0 replaces every texel
        if (iteration_ >= iterations_) {
            upload(shading_block());
            return;
        }
        const int total = probe_count();
        const long long budget = options_.budget;
        // Probes this frame: all remaining iterations (a still), or what gi.budget rays buy.
        long long probes_left = budget <= 0 ? static_cast<long long>(iterations_ - iteration_ + kRelocationRounds - relocation_rounds_) * total - cursor_
                                            : std::max<long long>(1, budget / rays_);
        const GLuint trace = env.programs.get("gi_trace").id();
        const GLuint update = env.programs.get("gi_update").id();
        frame_block_.width = frame_block_.height = frame_block_.sample_index = frame_block_.seed = 0;
        if (!frame_ubo_) frame_ubo_ = gl::Buffer(sizeof(rt::FrameGpu), nullptr, GL_DYNAMIC_STORAGE_BIT);
        frame_ubo_.update(0, sizeof(rt::FrameGpu), &frame_block_);
        rt::bind_scene(*rt_scene_, env.scene);
        glBindBufferBase(GL_UNIFORM_BUFFER, RT_FRAME_BINDING, frame_ubo_.id());
        glBindBufferBase(GL_UNIFORM_BUFFER, GI_BINDING, block_.id());
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, RT_DIAGNOSTICS_BINDING, diagnostics_.id());
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, GI_RAYS_BINDING, rays_buffer_.id());
        glBindTextureUnit(GI_IRRADIANCE_UNIT, irradiance_.id());
        glBindSampler(GI_IRRADIANCE_UNIT, sampler_.id());
        glBindTextureUnit(GI_DEPTH_UNIT, depth_.id());
        glBindSampler(GI_DEPTH_UNIT, sampler_.id());
        glBindTextureUnit(GI_RAYS_UNIT, rays_view_.id());
        glBindTextureUnit(GI_OFFSETS_UNIT, offsets_.id());
        glBindSampler(GI_OFFSETS_UNIT, sampler_.id());
        // Batches of at most 64 probes: short dispatches (no GPU watchdog trips on big grids).
        const int batch_max = 64;
        // Before the first update: probes inside geometry are moved out of it (probe_relocate.comp),
        // each round from a trace of every probe's hit distances alone (gi.on = -1: no shading),
        // in batches that count against the frame's budget like the updates' (the viewer).
        if (relocation_rounds_ < kRelocationRounds) {
            const GLuint relocate = env.programs.get("gi_relocate").id();
            while (probes_left > 0 && relocation_rounds_ < kRelocationRounds) {
                const int batch = static_cast<int>(std::min<long long>({probes_left, batch_max, total - cursor_}));
                gpu::GiData d = shading_block();
                d.on = -1.0f;
                d.first_probe = cursor_;
                d.seed = glm::uintBitsToFloat(0x2545F491u);
                d.rotation = random_rotation(static_cast<std::uint32_t>(relocation_rounds_), 2u);
                upload(d);
                ctx.state.use_program(trace);
                glDispatchCompute(static_cast<GLuint>(rays_ / 64), static_cast<GLuint>(batch), 1);
                ctx.counters.draw_calls += 1;
                probes_left -= batch;
                rays_last_frame_ += static_cast<long long>(batch) * rays_;
                cursor_ += batch;
                if (cursor_ >= total) {
                    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
                    glBindImageTexture(GI_OFFSETS_IMAGE, offsets_.id(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
                    ctx.state.use_program(relocate);
                    glDispatchCompute(static_cast<GLuint>((total + 63) / 64), 1, 1);
                    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
                    glBindImageTexture(GI_OFFSETS_IMAGE, 0, 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
                    ctx.counters.draw_calls += 1;
                    cursor_ = 0;
                    ++relocation_rounds_;
                }
            }
        }
        glBindImageTexture(GI_IRRADIANCE_IMAGE, irradiance_.id(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
        glBindImageTexture(GI_DEPTH_IMAGE, depth_.id(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_RG32F);
        while (probes_left > 0 && iteration_ < iterations_) {
            const int batch = static_cast<int>(std::min<long long>({probes_left, batch_max, total - cursor_}));
            gpu::GiData d = shading_block();
            // The trace reads the previous iteration (a bounce more), except with exactly one bounce.
            d.on = iteration_ > 0 && bounces_ > 1 ? 1.0f : 0.0f;
            d.first_probe = cursor_;
            d.weight = weight(iteration_);
            d.seed = glm::uintBitsToFloat(0x2545F491u);
            d.rotation = random_rotation(static_cast<std::uint32_t>(iteration_), 1u);
            upload(d);
            ctx.state.use_program(trace);
            glDispatchCompute(static_cast<GLuint>(rays_ / 64), static_cast<GLuint>(batch), 1);
            glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
            ctx.state.use_program(update);
            const int texels = (kIrradianceTexels + 2) * (kIrradianceTexels + 2) + (kDepthTexels + 2) * (kDepthTexels + 2);
            glDispatchCompute(static_cast<GLuint>(batch), static_cast<GLuint>((texels + 63) / 64), 1);
            glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
            ctx.counters.draw_calls += 2;
            probes_left -= batch;
            rays_last_frame_ += static_cast<long long>(batch) * rays_;
            cursor_ += batch;
            if (cursor_ >= total) {
                cursor_ = 0;
                ++iteration_;
            }
        }
        glBindImageTexture(GI_IRRADIANCE_IMAGE, 0, 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
        glBindImageTexture(GI_DEPTH_IMAGE, 0, 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
        unsigned diag = 0;
        glGetNamedBufferSubData(diagnostics_.id(), 0, sizeof diag, &diag);
        nonfinite_ = diag;
        upload(shading_block());
    }

    bool on_ = false, reset_ = true;
    std::vector<std::string> defines_;  // shading_defines: from the last upload to block_
    GiOptions options_;
    const Scene* scene_ = nullptr;
    std::unique_ptr<rt::RtScene> rt_scene_;
    std::uint64_t pose_version_ = 0;
    rt::FrameGpu frame_block_{};
    glm::ivec3 counts_{0};
    glm::vec3 spacing_{1.0f}, origin_{0.0f};
    int rays_ = 0, bounces_ = 0, iterations_ = 0;
    float bias_ = -1.0f, inset_ = -1.0f, max_distance_ = 1.0f, shading_bias_ = 0.0f;
    int iteration_ = 0, cursor_ = 0;
    // Rounds of probe relocation done since the grid was allocated (probe_relocate.comp).
    static constexpr int kRelocationRounds = 2;
    int relocation_rounds_ = 0;
    unsigned nonfinite_ = 0;
    long long rays_last_frame_ = 0;
    gl::Texture irradiance_, depth_, rays_view_, offsets_;
    gl::Buffer rays_buffer_, diagnostics_, block_, frame_ubo_;
    gl::Sampler sampler_;
    FrameGraph::ResourceId irr_id_ = -1, depth_id_ = -1;
};

class Gi final : public Effect {
public:
    const char* name() const override { return "gi"; }
    std::any default_options() const override { return GiOptions{}; }
    std::vector<Knob> knobs() const override {
        using O = GiOptions;
        return KnobRows<O>("gi", [](RenderSettings& s) -> O& { return s.get<O>(); })
            .integer("probes", &O::probes, 2, 32, "GI probes along the scene's longest axis (the other axes in proportion); given alone, exactly that many (gi.dense=0)")
            .boolean("dense", &O::dense, "more probes where they carry more of the image's light: gi.probes x sqrt(indirect share / 25 %), up to 2 gi.probes")
            .integer("rays", &O::rays, 64, 2048, "rays per probe and update (a multiple of 64)")
            .integer("bounces", &O::bounces, 0, 64, "updates that each add a bounce of light; 0: planned from the indirect estimate")
            .integer("iterations", &O::iterations, 1, 512, "probe updates after the bounces, which average noise (a still does them all before its frame)")
            .real("threshold", &O::threshold, 0.0f, 1.0f, "estimated indirect fraction of the image from which the probes run (0: always)")
            .real("indirect_only", &O::indirect_only, 0.0f, 1.0f,
                  "share of the surface in view lit visibly by indirect light alone from which the probes run whatever gi.threshold (1: never)")
            .integer("budget", &O::budget, 0, 1 << 26, "probe rays per frame (the viewer); 0: converge before the frame")
            .while_moving("4096")
            .boolean("restart", &O::restart, "start the probes over every frame (a scene that changes every frame; bench accuracy times the convergence so)")
            .real("inset", &O::inset, 0.01f, 0.5f, "distance of the outer probes from the scene's bounds, in cells (0.5: cell centres)")
            .real("bias", &O::bias, 0.0f, 1.0f, "shading offset off the surface, in units of 0.75 x the smallest probe spacing")
            .rows;
    }
    // Asking for a number of probes is asking for that many, unless gi.dense is given too.
    void complete_knobs(RenderSettings& s, const std::set<std::string>& given) const override {
        if (given.count("gi.probes") && !given.count("gi.dense")) s.get<GiOptions>().dense = false;
    }
    // The planner needs the estimate of the indirect light (estimate.hpp) unless gi.threshold is
    // 0 (always on) or GI is switched off.
    const char* view_estimate(const RenderSettings& s) const override {
        return s.on("gi") && s.get<GiOptions>().threshold > 0.0f ? "indirect estimate" : nullptr;
    }
    ViewEstimate estimate_view(const ViewEstimateInput& in) const override {
        IndirectEstimate e;
        try {
            e = estimate_indirect(in.shaders, in.scene, in.gpu, in.camera, in.aspect, in.tracer_scene);
        } catch (const Error& error) {
            if (error.code() == ExitCode::internal) throw;
            e = IndirectEstimate{};  // nothing to trace (e.g. no triangles): none planned
        }
        return {e, e.text()};
    }
    void estimate_json(const ViewEstimate& v, nlohmann::json& j) const override {
        if (const auto* e = std::any_cast<IndirectEstimate>(&v.value))
            j["indirect_estimate"] = {{"fraction", e->fraction}, {"indirect_only_share", e->indirect_only_share}, {"ms", e->ms}, {"width", e->width}, {"height", e->height}, {"spp", e->spp}};
    }
    // Planned by what it contributes: the estimate of the indirect fraction (the renderer traces
    // it at set-up, estimate.hpp) against gi.threshold. Always gated: a scene whose indirect
    // light is below the threshold does get a little, so forcing it on would change the image.
    EffectDecision decide(const Features& f, const RenderSettings& s) const override {
        const GiOptions& o = s.get<GiOptions>();
        const IndirectEstimate* e = indirect_estimate(f);
        bool needed = false;
        std::string why;
        char pct[32];
        std::snprintf(pct, sizeof pct, "%.0f %%", o.threshold * 100.0);
        if (f.source && f.source->triangle_count() == 0) why = "no geometry to bounce light";
        else if (o.threshold <= 0.0f) needed = true, why = "gi.threshold=0 (always)";
        else if (!e) why = "no estimate of the indirect light (it needs the tracer: a GL context)";
        else if (!e->trusted) {
            // Too little of the view is lit to measure a ratio: run the probes rather than risk
            // losing the light.
            needed = true;
            why = "indirect light is " + e->text() + ", so the probes run";
        } else {
            needed = e->fraction >= o.threshold;
            why = "indirect light is " + e->text() + (needed ? ", at least" : ", below") + " gi.threshold " + pct;
            // A region that only indirect light lights goes black without the probes, however
            // small the image-wide fraction.
            if (!needed && o.indirect_only < 1.0f && e->indirect_only_share >= o.indirect_only) {
                needed = true;
                char only[96];
                std::snprintf(only, sizeof only, ", but %.1f %% of the surface is lit by it alone, at least gi.indirect_only %.1f %%",
                              e->indirect_only_share * 100.0, o.indirect_only * 100.0);
                why += only;
            }
        }
        if (needed) why += "; " + std::to_string(gi_planned_bounces(o, e)) + " bounce(s), " + std::to_string(gi_planned_probes(o, e)) + " probes along the longest axis";
        return decide_effect(name(), s.on(name()), needed, why, true);
    }
    void plan(Stage stage, const Features& f, const RenderSettings& s, std::vector<PlannedPass>& out) const override {
        if (stage != Stage::light_views) return;
        const GiOptions& o = s.get<GiOptions>();
        const IndirectEstimate* e = indirect_estimate(f);
        std::string why = "probe updates with the tracer (" + std::to_string(rounded_rays(o.rays)) + " rays per probe, " +
                          std::to_string(gi_planned_bounces(o, e)) + " bounces, " +
                          (o.budget > 0 ? std::to_string(o.budget) + " rays per frame)" : "converged before the frame)");
        out.push_back({"gi_probes", why, this, {"gi_trace", "gi_update"}});
        out.back().work = runtime_pass<GiRuntime>([](GiRuntime& r, const PassSite& p) { r.add_probes(p.graph, p.env); });
    }
    std::vector<ProgramDesc> programs() const override {
        using S = ShaderStage;
        return {{"gi_trace", {{S::compute, "effects/gi/probe_trace.comp"}}, {"HAS_EMITTERS", "HAS_MASK"}},
                {"gi_update", {{S::compute, "effects/gi/probe_update.comp"}}, {}},
                {"gi_relocate", {{S::compute, "effects/gi/probe_relocate.comp"}}, {}}};
    }
    std::vector<GpuBlockInfo> gpu_blocks() const override { return {{"GiData", GI_BINDING, sizeof(gpu::GiData), "forward"}}; }
    const char* shading_include() const override { return "effects/gi/gi_shading.glsl"; }
    std::vector<ShadingHook> shading_hooks() const override { return {ShadingHook::indirect_light, ShadingHook::carries_sky}; }
    std::unique_ptr<EffectRuntime> create_runtime() const override { return std::make_unique<GiRuntime>(); }
    std::vector<AccuracySweep> accuracy_sweeps(bool quick) const override { return gi_accuracy_sweeps(quick); }
    std::vector<std::string> interactive_defaults() const override { return {"gi.budget=" + std::to_string(kGiInteractiveBudget)}; }
};

}  // namespace

int gi_planned_bounces(const GiOptions& o, const IndirectEstimate* estimate) {
    if (o.bounces > 0) return o.bounces;
    int k = 1;
    if (!estimate) {
        k = static_cast<int>(std::ceil(std::log(0.005) / std::log(0.5))) - 1;
    } else {
        // Bounce j >= 2 carries B2 r^(j-2) (the measured second bounce, then the ratio the third
        // had to it): after k bounces B2 r^(k-1) / (1 - r) is left out. Enough bounces to leave
        // less than 0.5 % of the image's light.
        const double r = std::clamp(estimate->per_bounce, 0.0, 0.95);
        const double b1 = estimate->one_bounce_mean;
        const double b2 = estimate->two_bounce_mean > 0.0 ? estimate->two_bounce_mean : r * b1;
        const double total = estimate->direct_mean + b1 + b2 / (1.0 - r);
        if (total > 0.0 && b2 > 0.0)
            while (k < 64 && b2 * std::pow(r, k - 1) / (1.0 - r) > 0.005 * total) ++k;
    }
    // The averaging updates after the bounces keep adding one each (their mean is about
    // iterations/2 bounces more), so the replacing updates need that many fewer. But only when
    // there are at least two: with exactly one the updates never read the probes (GiRuntime::
    // update), so the averaging adds no bounce, and a scene that needs more than one must not
    // be cut to one (a closed room lost every bounce after the first: -11 % of its image).
    if (k <= 1) return 1;
    return std::clamp(k - o.iterations / 2, 2, 32);
}

int gi_planned_probes(const GiOptions& o, const IndirectEstimate* estimate) {
    if (!o.dense || !estimate) return o.probes;
    const double share = std::clamp(estimate->fraction, 0.0, 1.0);
    const int planned = static_cast<int>(std::lround(o.probes * std::sqrt(share / 0.25)));
    return std::clamp(planned, o.probes, std::min(2 * o.probes, 32));
}

const IndirectEstimate* indirect_estimate(const Features& f) {
    const ViewEstimate* v = f.estimate("gi");
    return v ? std::any_cast<IndirectEstimate>(&v->value) : nullptr;
}

std::string gi_status_line(const GiStatus& st, int budget) {
    if (!st.planned) return {};
    char head[128];
    std::snprintf(head, sizeof head, "GI probes %dx%dx%d, %d rays, %d bounce(s): ", st.counts.x, st.counts.y, st.counts.z,
                  st.rays, st.bounces);
    std::string line = head;
    if (st.converged()) {
        line += "converged (" + std::to_string(st.updates_planned) + " updates";
        line += budget > 0 ? ")" : ", before the frame: gi.budget=0)";
    } else {
        // Rays still owed, and the frames they take at this budget (the current update's
        // finished part is not known here: an upper bound).
        const long long per_update = static_cast<long long>(st.counts.x) * st.counts.y * st.counts.z * st.rays;
        const long long owed = static_cast<long long>(st.updates_planned - st.updates_done) * per_update;
        line += std::to_string(st.updates_done) + "/" + std::to_string(st.updates_planned) + " updates done (converging, ";
        if (budget > 0) {
            const long long per_frame = std::max<long long>(budget, st.rays);
            line += std::to_string(budget) + " rays/frame, <= " + std::to_string((owed + per_frame - 1) / per_frame) + " frames to go)";
        } else {
            line += "gi.budget=0: the next frame)";
        }
    }
    if (st.nonfinite > 0) line += "; " + std::to_string(st.nonfinite) + " non-finite ray results replaced by 0";
    return line;
}

const Effect& gi_effect() {
    static const Gi effect;
    return effect;
}

}  // namespace candela
