#pragma once
// The interface of an effect module (docs/design.md, docs/adding-an-effect.md), which the base
// declares and each folder under engine/effects/ implements: the effect's options and knob rows,
// its planning (on/off with the reason, the passes it adds), its passes, programs and persistent
// GPU resources, its uniform block (a header shared by C++ and GLSL) and its accuracy sweep.
// effects/registry.cpp lists them (render/effect_registry.hpp); the renderer, the planner,
// `info`, the stats JSON, the viewer and `bench accuracy` iterate it and know no effect by name.
#include <any>
#include <functional>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <nlohmann/json_fwd.hpp>

#include "render/knob.hpp"
#include "render/frame_graph.hpp"
#include "render/gpu_scene.hpp"
#include "render/shading_hooks.hpp"
#include "shader/shader_library.hpp"

namespace candela {

struct AccuracySweep;  // effects/accuracy_sweep.hpp: what the accuracy engine runs
struct Bounds;
struct Camera;
struct EffectDecision;
struct Scene;
struct Features;
struct ViewInput;
namespace gpu { struct FrameData; }
namespace rt { class RtScene; }
using gpu::FrameData;
struct FrameTargets;
struct PassEnv;
struct PlannedPass;
struct RenderSettings;
class GpuScene;
class ProgramCache;
class EffectRuntime;

// Where a planned pass adds its work (PlannedPass::work): the frame's graph, the passes'
// environment, the targets of the pass's stage and, for an effect's pass, the effect's runtime.
struct PassSite {
    FrameGraph& graph;
    const PassEnv& env;
    FrameTargets& targets;
    EffectRuntime* runtime;
};
using PassWork = std::function<void(const PassSite&)>;
// An effect's pass whose work is `f(runtime, site)`, with the runtime as its own type R.
template <class R, class F>
PassWork runtime_pass(F f) {
    return [f](const PassSite& s) { f(static_cast<R&>(*s.runtime), s); };
}

// Where in the frame an effect's passes go. The base passes (render/) sit between them:
//   light_views | geometry (G-buffer or depth/normal prepass) | screen | lighting |
//   after_lighting | sky | blended | post | tonemap
enum class Stage {
    light_views,     // views from the lights or probes, before the camera's geometry
    screen,          // screen-space buffers from the camera's depth and normals, before lighting
    after_lighting,  // drawn over the lit opaque image, before the sky
    blended,         // after the sky: blended surfaces
    // After everything is drawn: first the pass that resolves the drawing targets into the output
    // when an effect decided the frame's sampling (FrameSampling::resolved: FrameTargets::samples
    // is 1 afterwards), then filters of the final radiance, before the tonemap.
    post,
};

// A uniform block declared in an effect's *_data.h (gpu/gpu_block.h): its GLSL block name,
// its binding and the size the C++ struct has, which a test checks against the GL's layout.
struct GpuBlockInfo {
    const char* block;  // GLSL block name, e.g. "SsaoData"
    int binding;
    std::size_t size;   // sizeof the C++ struct
    const char* program;  // a program that declares it
};

// How a frame takes its samples; the planned effects fill it in (Effect::frame_sampling, at
// most one of them changes it). The default is one sample at each pixel centre, drawn once.
struct FrameSampling {
    // The scene is drawn into targets of its own, which the deciding effect's Stage::post pass
    // resolves into the output (the first colour pass creates them); false: drawn into the output.
    bool resolved = false;
    int samples = 1;    // samples per pixel of the drawing targets (more than 1: multisampled)
    // The device's positions of those samples, pixel units from the pixel centre, y up (the
    // deferred lighting tells the samples of an edge pixel apart with them).
    std::vector<glm::vec2> positions{glm::vec2(0.0f)};
    // The frame is drawn `subframes` times, sub-frame k with the projection shifted by offsets[k]
    // pixels (x right, y up); passes marked PlannedPass::every_subframe accumulate them and the
    // other post passes run after the last one only.
    int subframes = 1;
    std::vector<glm::vec2> offsets{glm::vec2(0.0f)};
    // Multisampled: MASK materials cover samples in proportion to their alpha (alpha to coverage).
    bool coverage = false;
    // The variance (pixels^2) of the pixel filter the shading widens specular lobes by (the
    // normal's screen-space derivatives times it add to the NDF's alpha^2); 0: none, the pixel
    // centre's value is the estimate.
    float specular_filter_variance = 0.0f;
};

// What an effect measures of the view before the planner decides (Effect::view_estimate): traced
// once per renderer from the first frame's camera at its aspect.
struct ViewEstimate {
    std::any value;    // the effect's own measurement (its decide() reads Features::estimates)
    std::string text;  // one line for `candela info` and the log
};
// By the name of the effect that made it.
using ViewEstimates = std::map<std::string, ViewEstimate>;

// What an effect's view estimate may use.
struct ViewEstimateInput {
    const ShaderLibrary& shaders;
    const Scene& scene;
    GpuScene& gpu;
    const Camera& camera;
    float aspect;
    // Optional, in and out: the tracer geometry of the caller's earlier measurements of this
    // scene (rt::RayTracer::shared_scene), to use and keep, so that the BVH is built once.
    std::shared_ptr<rt::RtScene>* tracer_scene = nullptr;
};

// What the light buffer holds (GpuScene::update_lights); effects fill in their part.
struct LightSetup {
    int area_samples = 0;   // raster pieces per emissive primitive (0: emitters are not lights)
    EmitterSplitter split_emitters = nullptr;  // what makes those pieces (render/gpu_scene.hpp)
    bool shadows = false;   // lights get shadow views
    int cascades = 1;       // views of a directional light
    int max_shadowed = 0;   // lights with shadow views at most
    int shadow_resolution = 1024;     // texels a side of a full-resolution shadow view
    double shadow_budget_mb = 512.0;  // the shadow maps' memory at most (GpuScene::shadow_atlas)
    float cutoff = 0.0f;    // lights.cutoff: the reach of point and spot lights without a range
};

class Effect {
public:
    virtual ~Effect() = default;
    // The name of `--effects`, of the knob prefix (`ssao.samples`) and of the JSON keys.
    virtual const char* name() const = 0;
    virtual bool on_by_default() const { return true; }
    // False for an effect that always runs when the scene calls for it (not in --effects).
    virtual bool switchable() const { return true; }
    // A default-constructed options struct of this effect, and its knob rows (prefix name()).
    virtual std::any default_options() const = 0;
    virtual std::vector<Knob> knobs() const = 0;
    // The prefixes of its knob names: name() unless the effect keeps older names ("probe.*").
    virtual std::vector<std::string> knob_groups() const { return {name()}; }
    // After a list of --set assignments (apply_knobs): a knob given alone may imply another of
    // this effect's (aa.samples=4 alone turns aa.mode to msaa). `given`: the knob names set.
    virtual void complete_knobs(RenderSettings& /*s*/, const std::set<std::string>& /*given*/) const {}

    // Non-null (what it measures, e.g. "indirect estimate") when the effect decides from a
    // measurement of the view with these settings: the renderer (and `info`) then asks
    // estimate_view() once before planning and hands the result to decide() in
    // Features::estimates. Needs a GL context (the tracer).
    virtual const char* view_estimate(const RenderSettings& /*s*/) const { return nullptr; }
    // Throws candela::Error (internal) when the tracer cannot be built.
    virtual ViewEstimate estimate_view(const ViewEstimateInput& /*in*/) const { return {}; }
    // The estimate's fields in the planner's JSON (to_json(Features)).
    virtual void estimate_json(const ViewEstimate& /*e*/, nlohmann::json& /*features*/) const {}
    // True when the effect's plan with these settings depends on the GL device (its sample
    // counts, say): `info` then plans with a context.
    virtual bool plans_with_device(const RenderSettings& /*s*/) const { return false; }

    // Whether the scene calls for the effect, and so whether it runs. `f` already holds the
    // decisions of the effects before this one in the registry (an effect may depend on them).
    virtual EffectDecision decide(const Features& f, const RenderSettings& s) const = 0;
    // The passes the planned effect adds at `stage`, in order, each with its reason and programs.
    virtual void plan(Stage stage, const Features& f, const RenderSettings& s, std::vector<PlannedPass>& out) const = 0;
    // A number the effect decides from that changes with the view between frames without a
    // settings change (dof: the lens's aperture; motion_blur: the draws in view that move during
    // the shutter); 0 when the effect needs none. The renderer measures it every frame and
    // re-plans when it turns zero or non-zero; decide() reads it as Features::view_amount(name()).
    virtual double view_amount(const ViewInput& /*in*/) const { return 0.0; }
    // Non-empty when the planned effect reads the camera's depth and normals before shading (the
    // forward path then adds a depth/normal prepass; the text names it in the pass's reason).
    virtual const char* needs_depth_normals() const { return nullptr; }
    // True when the planned effect draws the BLEND materials itself (otherwise the opaque passes
    // draw them as opaque).
    virtual bool draws_blended_surfaces() const { return false; }
    // Its part of the light buffer's layout (decided with the features, before the path).
    virtual void light_setup(const RenderSettings& /*s*/, const EffectDecision& /*d*/, LightSetup& /*out*/) const {}
    // The planned effect's say in how the frame takes its samples (multisampled targets,
    // sub-frames: FrameSampling); called in registry order on the planned effects only.
    virtual void frame_sampling(const Features& /*f*/, const RenderSettings& /*s*/, FrameSampling& /*out*/) const {}
    // The GLSL file (path from the effects root, e.g. "effects/ssao/ssao_shading.glsl") that the
    // lighting code (shaders/lighting/shading.glsl) includes for what this effect adds to the
    // shading; nullptr: none. The registry's order is the include order.
    virtual const char* shading_include() const { return nullptr; }
    // The lighting's hook points (render/shading_hooks.hpp) this effect provides: for each hook H,
    // its shading include defines `<name()>_<H's name>` with H's parameters.
    virtual std::vector<ShadingHook> shading_hooks() const { return {}; }

    // Every program this effect can build (the catalog: `candela shaders check`, hot reload).
    virtual std::vector<ProgramDesc> programs() const { return {}; }
    virtual std::vector<GpuBlockInfo> gpu_blocks() const { return {}; }
    // The renderer's per-effect state: persistent GPU resources and the frame's passes.
    virtual std::unique_ptr<EffectRuntime> create_runtime() const = 0;
    // The effect's accuracy sweeps as data (effects/accuracy_sweep.hpp), which `bench accuracy`
    // runs against the tracer; every effect has at least one (quick: the CI's smaller set).
    virtual std::vector<AccuracySweep> accuracy_sweeps(bool quick) const = 0;
    // Knob assignments ("name.knob=value") that an interactive front end (the viewer) applies
    // unless the user set that knob: settings that keep every frame interactive where a still
    // would rather converge before its one frame.
    virtual std::vector<std::string> interactive_defaults() const { return {}; }
    // What `candela info` adds about the effect's plan for a view (`view_proj`) when the effect is
    // planned: lines such as "reflection probes: ..." (each "name: what"), after the passes.
    virtual std::vector<std::string> info_lines(const Scene& /*scene*/, const RenderSettings& /*s*/, const glm::mat4& /*view_proj*/) const {
        return {};
    }
};

// How far an effect that converges over frames has got (EffectRuntime::progress): the viewer's
// panel shows `line` under the effect's row, and its log prints it when the phase changes.
struct EffectProgress {
    bool active = false;            // converging or converged (false: nothing to report)
    bool converged = false;
    int steps_done = 0;             // completed steps so far; falls back when the effect restarts
    long long work_last_frame = 0;  // work the last frame did (rays, samples; 0: none)
    std::string line;               // e.g. "GI probes 8x4x2, 128 rays, 5 bounce(s): 3/11 updates done (...)"
    std::string pace;               // the knob that spreads the work over frames, e.g. "gi.budget 16384 rays/frame"
};

// What an effect's runtime sees when the renderer's settings change (Renderer::set_settings).
struct EffectSetup {
    const Scene& scene;
    GpuScene& gpu;
    const RenderSettings& settings;
    const Features& features;
    const EffectDecision& decision;  // this effect's
};

// What an effect's runtime sees before a frame's graph is built.
struct FramePrep {
    const RenderSettings& settings;
    const Features& features;
    const EffectDecision& decision;  // this effect's
    GpuScene& gpu;
    const Camera& camera;
    float aspect;
    const Bounds& scene_bounds;
    int width, height;
    FrameData& frame;                // the frame's constants, before upload
    // Every effect's runtime, registry order (prepared before this one: those earlier in it).
    const std::vector<EffectRuntime*>& effects;
    template <class Runtime>
    const Runtime* runtime() const {
        for (const EffectRuntime* e : effects)
            if (const auto* r = dynamic_cast<const Runtime*>(e)) return r;
        return nullptr;
    }
};

class EffectRuntime {
public:
    virtual ~EffectRuntime() = default;
    // Every frame, planned or not, before the graph: persistent resources and the uniform block
    // (an effect that is not planned uploads its "off" block, which the shading passes still read).
    virtual void prepare(const FramePrep& /*prep*/) {}
    // After set-up or new settings: placement, persistent resources that depend on them.
    virtual void configure(const EffectSetup& /*setup*/) {}
    // The frame's graph exists: import the persistent textures the passes read or write.
    virtual void begin_graph(FrameGraph& /*graph*/) {}
    // The scene changed behind the renderer's back: drop cached captures (probes).
    virtual void invalidate() {}
    // Textures the effect owns that the viewer's buffer inspector can show, by name.
    virtual void inspectables(std::vector<std::pair<std::string, const gl::Texture*>>& /*out*/) const {}
    // The shading passes (forward, deferred, blended, probe capture) read what this effect made:
    // declare those reads, and bind the effect's textures, buffers and uniform block.
    virtual void read_shading_inputs(FrameGraph::Builder& /*b*/) const {}
    virtual void bind_shading_inputs(const PassEnv& /*env*/, FrameGraph::Context* /*ctx*/) const {}
    // GLSL defines ("NAME" or "NAME VALUE") that specialise the lighting programs (forward,
    // deferred lighting) to the uniform block bind_shading_inputs binds, as it is now: each
    // leaves out code whose condition that block makes false. Kept on the CPU wherever the block
    // is uploaded (not read back from GL). The renderer concatenates them in registry order.
    virtual std::vector<std::string> shading_defines() const { return {}; }
    // For an effect whose result converges over frames: how far it has got (after render()).
    virtual EffectProgress progress() const { return {}; }
};

}  // namespace candela
