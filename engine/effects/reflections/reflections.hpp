#pragma once
// Reflections (engine/effects/reflections/): reflection probes captured with the forward path
// and GGX-prefiltered (the env_probe pass), read by the shading of smooth metals and refracting
// surfaces (reflections_shading.glsl); on the deferred path a transmissive pass re-shades the
// transmissive surfaces. Probe placement: probes.hpp.
#include "render/effect.hpp"
#include "effects/reflections/probes.hpp"
#include "render/gpu_scene.hpp"

namespace candela {

enum class ProbeUpdate { once, every_frame };
inline constexpr ChoiceName<ProbeUpdate> kProbeUpdates[] = {{"once", ProbeUpdate::once}, {"every_frame", ProbeUpdate::every_frame}};
enum class ProbePlacementMode { scene, automatic };
inline constexpr ChoiceName<ProbePlacementMode> kProbePlacements[] = {{"scene", ProbePlacementMode::scene},
                                                                      {"auto", ProbePlacementMode::automatic}};

struct ReflectionsOptions {
    float max_roughness = 0.3f;  // [0, 1] metallic surfaces rougher than this need no reflection pass
    int probe_resolution = 128;  // [16, 1024] face size of each reflection probe (probe.resolution)
    ProbeUpdate update = ProbeUpdate::once;  // once re-captures when the scene or settings change
    // scene: extras.reflection_probe nodes (auto if none); auto: planned (probes.hpp plan_probes)
    ProbePlacementMode placement = ProbePlacementMode::scene;
    int probe_budget = 8;       // [1, 64] at most this many automatic probes (probe.budget)
    float probe_merge = 0.25f;  // [0, 4] parallax error under which objects share a probe (probe.merge)
    int probe_samples = 32;  // [1, 1024] GGX samples per texel of the prefiltered levels (probe.samples)
    bool parallax = true;    // probes without a box march their distance cube (probe.parallax)
};

const Effect& reflections_effect();

// The effect's state in a renderer (Renderer::effect_runtime<ReflectionsRuntime>()).
class ReflectionsRuntime final : public EffectRuntime {
public:
    // The probes of this scene and settings (empty when the effect is not planned; automatic
    // probes are planned again from the first frame's view), and the plan's one-line summary.
    const std::vector<ProbePlacement>& placements() const;
    const std::string& plan_summary() const { return summary_; }

    void configure(const EffectSetup& setup) override;
    void prepare(const FramePrep& prep) override;
    void begin_graph(FrameGraph& graph) override;
    // The pass env_probe: the probes captured (again, if they must be) in this frame.
    void add_probes(FrameGraph& graph, const PassEnv& env);
    // The pass transmissive (deferred path): transmissive surfaces shaded forward over the lit image.
    void add_transmissive(FrameGraph& graph, const PassEnv& env, FrameTargets& targets);
    void read_shading_inputs(FrameGraph::Builder& b) const override;
    void bind_shading_inputs(const PassEnv& env, FrameGraph::Context* ctx) const override;
    std::vector<std::string> shading_defines() const override { return defines_; }
    void invalidate() override { res_.valid = false; }
    void inspectables(std::vector<std::pair<std::string, const gl::Texture*>>& out) const override;

private:
    void place(const FramePrep& prep);
    void prepare_faces(const FramePrep& prep);
    void add_capture(FrameGraph& graph, const PassEnv& env);

    // Captured by the env_probe pass into `capture` (level 0 of each face, then a box-filtered
    // chain), prefiltered into `filtered`, which the shading passes read.
    struct Resources {
        std::vector<ProbePlacement> placements;
        gl::Texture capture;   // cube-map array, full mip chain
        gl::Texture filtered;  // cube-map array, prefiltered_levels(size) levels
        gl::Texture depth;     // size x size, shared by every face
        gl::Texture distance;  // R32F cube-map array: distance to what each texel saw (parallax)
        std::vector<gl::Framebuffer> face_fbos;  // per cube face (layer 6 probe + face)
        gl::Buffer frames;     // FrameData per face at `frame_stride` bytes
        std::vector<glm::mat4> face_view_proj;  // per face (layer): what it sees (culling)
        GLsizeiptr frame_stride = 0;
        float znear = 0.0f;    // the faces' near plane
        gl::Buffer data;       // ProbeData per probe
        int size = 0, cubes = 0, levels = 0;
        bool valid = false;    // captured for the current scene and settings
        bool sky = false;      // draw the environment behind the captured geometry
    } res_;
    ReflectionsOptions options_;
    Bounds scene_bounds_;
    const Scene* scene_ = nullptr;  // set by configure when the effect is planned
    GpuScene* gpu_ = nullptr;
    bool placed_ = false;      // res_.placements planned for the current scene and settings
    std::string summary_;      // what was planned (logged once per plan)
    gl::Buffer block_, capture_block_;  // ReflectionsData for the camera's view and for probe faces
    bool on_ = false;                   // probes are bound for shading this frame
    std::vector<std::string> defines_;  // shading_defines: what block_ turns off
    FrameGraph::ResourceId probes_id_ = -1;
};

}  // namespace candela
