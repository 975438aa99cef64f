#pragma once
// What every pass of a frame shares: the scene on the GPU, the settings, the frame constants,
// the programs and a framebuffer cache; plus the draw helper of the forward-style passes.
#include <map>
#include <string>
#include <vector>

#include "gl/handles.hpp"
#include "gl/state.hpp"
#include "render/frame_graph.hpp"
#include "render/environment.hpp"
#include "render/gpu_scene.hpp"
#include "render/program_cache.hpp"
#include "render/settings.hpp"

namespace candela {

class EffectRuntime;
struct FrameSampling;

// FBOs keyed by their attachments; pool textures live across frames, so these hit every frame.
class FramebufferCache {
public:
    GLuint get(const std::vector<const gl::Texture*>& colors, const gl::Texture* depth);
    void clear() { fbos_.clear(); }

private:
    std::map<std::vector<GLuint>, gl::Framebuffer> fbos_;
};

struct PassEnv {
    GpuScene& scene;
    const RenderSettings& settings;
    const FrameData& frame;
    int width;
    int height;
    const gl::Buffer& frame_ubo;
    FramebufferCache& fbos;
    ProgramCache& programs;   // every planned pass's programs are built (Renderer::set_settings)
    const gl::VertexArray& empty_vao;
    const gl::Sampler& linear_clamp;   // for screen-space buffers read at other resolutions
    const ImageBasedLighting& ibl;
    const gl::Texture& env_cube;  // the static environment's prefiltered cube (empty: none)
    // The effect modules' runtimes (engine/effects/), registry order: the shading passes let each
    // declare and bind what it made.
    const std::vector<EffectRuntime*>& effects;
    // How the frame takes its samples (render/effect.hpp): multisampled targets, alpha to
    // coverage, sub-frames. This is sub-frame `subframe` of sampling.subframes.
    const FrameSampling& sampling;
    int subframe = 0;
    // The forward pass's per-tile light masks (light_tiles.comp), grown as needed; owned by the renderer.
    gl::Buffer* light_tiles = nullptr;
};

// The resources the forward chain passes along.
struct FrameTargets {
    FrameGraph::ResourceId hdr = -1;
    FrameGraph::ResourceId depth = -1;
    FrameGraph::ResourceId display = -1;  // RGBA8 display values (tonemap pass)
    FrameGraph::ResourceId gbuffer[3] = {-1, -1, -1};  // layout: shaders/lighting/gbuffer.glsl
    FrameGraph::ResourceId normals = -1;  // xy octahedral normal: gbuffer[1] or the prepass's
    bool prepass_has_blend = false;       // the depth prepass drew BLEND materials as opaque
    // Deferred: the G-buffer's depth. Multisampled, targets.depth is its single-sample copy
    // (gbuffer_resolve) during Stage::screen; deferred_lighting makes it targets.depth again.
    FrameGraph::ResourceId gbuffer_depth = -1;
    // Samples per pixel of the drawing targets (FrameSampling::samples): with more than one, the
    // first pass that draws colour creates `hdr` and `depth` multisampled; the screen-space
    // buffers (a depth/normal prepass, the screen-stage effects' buffers) stay single-sample.
    int samples = 1;
    // At Stage::post: the targets the scene was drawn into (the resolve reads them); `hdr` and
    // `depth` of the post targets are single-sample.
    const FrameTargets* drawn = nullptr;
};

// Binds the frame UBO, material and light SSBOs, the environment textures and what every effect
// module gives the shading that is not a frame-graph resource (its uniform block, persistent maps).
void bind_scene_buffers(const PassEnv& env);
// One full-screen triangle (the vertex shader makes it from gl_VertexID) into `fbo` at w x h with
// `program`, default pipeline state; counted as one draw call.
void draw_fullscreen(const PassEnv& env, FrameGraph::Context& ctx, GLuint fbo, int w, int h, GLuint program);
// Declares the reads of a shading pass: every effect module's shading inputs this frame.
void read_lighting_inputs(FrameGraph::Builder& b, const PassEnv& env);
// Binds every effect module's shading inputs, frame-graph textures included.
void bind_effect_inputs(const PassEnv& env, FrameGraph::Context& ctx);
// The forward program shading into the HDR target over the frame's depth with `ps`, every
// lighting input bound: the passes that draw after the opaque geometry.
void begin_forward_shading(const PassEnv& env, FrameGraph::Context& ctx, const FrameTargets& targets,
                           const gl::PipelineState& ps);
// The forward program specialised to this frame (the blocks bind_scene_buffers binds): the
// "forward" catalog program with the base's NO_* defines and every effect's
// EffectRuntime::shading_defines (forward/forward.frag); `may_peel` false: u_peel stays 0.
std::string forward_program_name(const PassEnv& env, bool may_peel, bool tiled_lights = false);
// The scene's materials have layers and render.material_layers is on: programs compile with
// MATERIAL_LAYERS and the image array is bound (shaders/common/material_layers.glsl).
bool material_layers_on(const PassEnv& env);
// The deferred lighting program `base` (deferred_light, deferred_light_ms, ..._edges) with the
// same lighting defines (deferred/light.comp honours them).
std::string deferred_light_program_name(const PassEnv& env, const std::string& base);
// Draws one scene item with `program` (default: forward), which has the forward vertex layout and
// per-draw uniforms (locations 0-3), textures and winding.
// `depth_only`: a program with only the model matrix, the material and the base colour texture
// (shadow casters).
void draw_item(const PassEnv& env, FrameGraph::Context& ctx, const GpuScene::Draw& d, bool cull, GLenum cull_face,
               GLuint program = 0, bool depth_only = false);

// The passes, in the order the renderer adds them.
void add_gbuffer_pass(FrameGraph& graph, const PassEnv& env, FrameTargets& targets, bool blend_as_opaque);
void add_gbuffer_resolve_pass(FrameGraph& graph, const PassEnv& env, FrameTargets& targets);
void add_deferred_lighting_pass(FrameGraph& graph, const PassEnv& env, FrameTargets& targets);
void add_depth_prepass(FrameGraph& graph, const PassEnv& env, FrameTargets& targets);
void add_depth_normal_prepass(FrameGraph& graph, const PassEnv& env, FrameTargets& targets, bool blend_as_opaque);
// `tiled_lights`: the lights are culled per 16x16 tile first (forward/light_tiles.comp into
// env.light_tiles) and the forward program walks the tile's lights (TILED_LIGHTS).
void add_forward_opaque_pass(FrameGraph& graph, const PassEnv& env, FrameTargets& targets, bool blend_as_opaque, bool tiled_lights);
void add_sky_pass(FrameGraph& graph, const PassEnv& env, FrameTargets& targets);
void add_tonemap_pass(FrameGraph& graph, const PassEnv& env, FrameTargets& targets, const gl::Texture& display,
                      float exposure_ev);

}  // namespace candela
// Note: the execute steps keep references to `env` and `targets`; both must outlive the graph's
// execute() (the renderer keeps them on its stack for the whole frame).
