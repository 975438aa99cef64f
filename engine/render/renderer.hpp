#pragma once
// The raster renderer: every frame, a frame graph of only the passes this scene and these
// settings call for (features.hpp), compiled, executed with per-pass GPU/CPU timing and counters.
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string_view>
#include <string>
#include <vector>

#include "gl/state.hpp"
#include "image/image.hpp"
#include "profile/gpu_timer.hpp"
#include "render/features.hpp"
#include "render/frame_graph.hpp"
#include "render/gpu_scene.hpp"
#include "render/passes/pass_env.hpp"
#include "render/program_cache.hpp"
#include "render/effect.hpp"
#include "render/settings.hpp"
#include "shader/shader_library.hpp"

namespace candela {

struct PassStats {
    std::string name;
    double gpu_ms = -1.0;  // -1: not measured (yet)
    double cpu_ms = 0.0;
    PassCounters counters;
    // With synchronous timing: wall ms between a glFinish before and one after the pass (all of
    // its work, including what a GPU timer does not see on llvmpipe: vertex shading, binning,
    // CPU work); -1 otherwise.
    double sync_ms = -1.0;
};

struct FrameReport {
    std::vector<PassStats> passes;                               // executed, in order
    std::vector<std::pair<std::string, std::string>> culled;     // pass, reason
    double graph_ms = 0.0;  // building + compiling the graph (CPU)
    int pool_allocations = 0;  // textures the pool has created so far
    int pool_slots = 0;
    int state_calls = 0, state_calls_skipped = 0;
};


// What a frame produces: linear radiance only (.exr, comparisons), or also display values
// (.png, a window) through the tonemap pass.
enum class FrameOutput { hdr, display };

class Renderer {
public:
    // Throws candela::Error (internal) if a shader does not build. `shaders` must outlive the
    // renderer (programs for newly planned passes are built from it on set_settings).
    // `shared_programs` (built from the same `shaders`, with the same context current): renderers
    // made one after another share compiled programs (a batch of renders), else the renderer owns its own.
    Renderer(const ShaderLibrary& shaders, const Scene& scene, GpuScene& gpu, const RenderSettings& settings,
             ProgramCache* shared_programs = nullptr);

    Renderer(const Renderer&) = delete;
    Renderer& operator=(const Renderer&) = delete;

    void set_settings(const RenderSettings& settings);
    // The view the planner measures the scene from (Effect::view_estimate): the first call,
    // or the first frame's camera and size, fixes it for the renderer's life. A caller that wants
    // features() planned before its first frame calls this first.
    void set_view(const Camera& camera, int width, int height);
    // Rebuilds every program that includes one of `changed` (shader files); a program that
    // fails keeps its last good version. Never throws for GLSL errors.
    ShaderReload reload_shaders(const std::vector<std::filesystem::path>& changed);
    const RenderSettings& settings() const { return settings_; }
    const Features& features() const { return features_; }

    // Renders one frame into the output texture (resized as needed).
    void render(const Camera& camera, int width, int height, FrameOutput output = FrameOutput::hdr,
                float exposure_ev = 0.0f);
    // Waits for this frame's GPU timer queries and fills last_frame().passes[].gpu_ms.
    void resolve_gpu_times();
    const FrameReport& last_frame() const { return report_; }
    ImageF read_radiance() const;
    // Display values of the last FrameOutput::display frame, 8-bit RGBA, top row first.
    std::vector<std::uint8_t> read_display() const;
    const gl::Texture& output() const { return output_; }
    const gl::Texture& display() const { return display_; }
    const TexturePool& pool() const { return pool_; }
    // The runtime of a registered effect, by its class (e.g. ReflectionsRuntime); nullptr if none.
    template <class Runtime>
    const Runtime* effect_runtime() const {
        for (const auto& e : effects_)
            if (const auto* r = dynamic_cast<const Runtime*>(e.get())) return r;
        return nullptr;
    }
    // The progress of the registered effect `name` (EffectRuntime::progress); inactive if unknown.
    EffectProgress effect_progress(std::string_view name) const;
    // Cached captures (reflection probes) are redone on the next frame: call after changing the scene.
    void invalidate_captures() {
        for (auto& e : effects_) e->invalidate();
    }
    const ImageBasedLighting& ibl() const { return ibl_; }
    const gl::Texture& environment_cube() const { return env_cube_; }
    // Buffer inspection (the viewer): keep the frame-graph resource `name` alive to the frame's
    // end (not aliased) so that inspected() returns it after render(); "" stops. Besides the
    // graph's resources: the textures effects own (EffectRuntime::inspectables: rsm_flux, probe_cube).
    void set_inspect(const std::string& name) { inspect_ = name; }
    const gl::Texture* inspected() const { return inspected_; }
    // The names that can be inspected after the last frame.
    const std::vector<std::string>& inspectable() const { return inspectable_; }
    // Measure every pass's wall time between glFinish calls (PassStats::sync_ms; stalls: for
    // benchmarks on software rasterizers, where timer queries miss the work done on the CPU).
    void set_synchronous_timing(bool on) { sync_timing_ = on; }
    // Debug: after each pass compare GL's state with the state cache's (stalls).
    void set_verify_state(bool on) { verify_state_ = on; }

private:
    // Analyzes and configures for settings_ and the last camera (features_, effects, programs).
    void plan();
    // One sub-frame: the frame's block, the planned passes as a frame graph, run and reported.
    void render_subframe(const Camera& camera, FrameOutput output, float exposure_ev, const FrameSampling& sampling, int sub);
    // The base's part of the frame's block (the effects' prepare() completes it).
    FrameData frame_data(const Camera& camera, const FrameSampling& sampling, int sub) const;
    // Declares the planned passes (each calls its work) and the tonemap on `graph`, drawing into
    // `targets` and filtering `post` (both must outlive the graph's execution), and marks the
    // outputs; returns the id of the resource the inspector asked for (-1: none).
    int declare_passes(FrameGraph& graph, const PassEnv& env, FrameTargets& targets, FrameTargets& post, FrameOutput output,
                       float exposure_ev, bool last);
    // Runs the compiled graph: GPU timers per pass, synchronous times into `sync_ms` when asked,
    // the state cache checked after each pass when asked (returns what went wrong, or "").
    std::string execute_graph(FrameGraph& graph, std::map<std::string, double>& sync_ms);
    // What the viewer's buffer inspector can show after this frame, and the texture it asked for.
    void collect_inspectables(const FrameGraph& graph, int inspected_id);
    // The sub-frame's executed and culled passes into the frame's report.
    void record_passes(const FrameGraph& graph, int sub, const std::map<std::string, double>& sync_ms);

    const ShaderLibrary& shaders_;
    std::optional<Camera> camera_;  // the last frame's camera (its lens plans depth of field)
    const Scene& scene_;
    GpuScene& gpu_;
    Bounds scene_bounds_;
    // What the effects measured of the view for the planner (Effect::view_estimate: traced once
    // per effect, from view_, on the first settings that ask).
    ViewEstimates estimates_;
    struct View {
        Camera camera;
        float aspect;
    };
    std::optional<View> view_;
    bool estimate_if_needed();  // true when it traced
    gl::Sampler linear_clamp_;
    ImageBasedLighting ibl_;
    gl::Texture env_cube_;   // static environment map, prefiltered (empty without a map)
    int env_cube_size_ = 0, env_cube_levels_ = 1;
    RenderSettings settings_;
    Features features_;
    ProgramCache own_programs_;
    ProgramCache& programs_;  // own_programs_ or the shared cache
    // One runtime per registered effect (engine/effects/registry.cpp), in registry order.
    std::vector<std::unique_ptr<EffectRuntime>> effects_;
    std::vector<EffectRuntime*> effect_ptrs_;
    gl::Buffer frame_ubo_;
    gl::VertexArray empty_vao_;
    gl::Texture output_;
    gl::Texture display_;
    int width_ = 0, height_ = 0;
    float aspect_ = 1.0f;
    gl::Buffer light_tiles_;  // the forward pass's per-tile light masks (PassEnv::light_tiles)  // of the last frame asked for (the effects' view amounts: Effect::view_amount)
    TexturePool pool_;
    FramebufferCache fbos_;
    gl::StateCache state_;
    GpuTimer timer_;
    FrameReport report_;
    bool verify_state_ = false;
    bool sync_timing_ = false;
    std::string inspect_;
    const gl::Texture* inspected_ = nullptr;
    std::vector<std::string> inspectable_;
    bool timer_warmed_ = false;
    std::uint64_t pose_version_ = 0;  // GpuScene::pose_version() the bounds and captures are for
    std::uint64_t material_version_ = 0;  // GpuScene::material_version() the view estimates are for
};

}  // namespace candela
