#pragma once
// What every pass of a frame shares: the scene on the GPU, the settings, the frame constants,
// the programs and a framebuffer cache; plus the draw helper of the forward-style passes.
#include <map>
#include <vector>

#include "gl/handles.hpp"
#include "gl/state.hpp"
#include "render/frame_graph.hpp"
#include "render/gpu_scene.hpp"
#include "render/settings.hpp"

namespace candela {

// FBOs keyed by their attachments; pool textures live across frames, so these hit every frame.
class FramebufferCache {
public:
    GLuint get(const std::vector<const gl::Texture*>& colors, const gl::Texture* depth);
    void clear() { fbos_.clear(); }

private:
    std::map<std::vector<GLuint>, gl::Framebuffer> fbos_;
};

struct Programs {
    gl::Program forward;
    gl::Program sky;
    gl::Program tonemap;
};

struct PassEnv {
    GpuScene& scene;
    const RenderSettings& settings;
    const FrameData& frame;
    int width;
    int height;
    const gl::Buffer& frame_ubo;
    FramebufferCache& fbos;
    const Programs& programs;
    const gl::VertexArray& empty_vao;
};

// The resources the forward chain passes along.
struct ForwardTargets {
    FrameGraph::ResourceId hdr = -1;
    FrameGraph::ResourceId depth = -1;
    FrameGraph::ResourceId display = -1;  // RGBA8 display values (tonemap pass)
};

// Binds the frame UBO, material and light SSBOs and the environment texture.
void bind_scene_buffers(const PassEnv& env);
// Draws one scene item with the forward program (per-draw uniforms, textures, winding).
void draw_item(const PassEnv& env, FrameGraph::Context& ctx, const GpuScene::Draw& d, bool cull, GLenum cull_face);

// The passes, in the order the renderer adds them.
void add_depth_prepass(FrameGraph& graph, const PassEnv& env, ForwardTargets& targets);
void add_forward_opaque_pass(FrameGraph& graph, const PassEnv& env, ForwardTargets& targets, bool blend_as_opaque);
void add_sky_pass(FrameGraph& graph, const PassEnv& env, ForwardTargets& targets);
void add_transparent_pass(FrameGraph& graph, const PassEnv& env, ForwardTargets& targets);
void add_tonemap_pass(FrameGraph& graph, const PassEnv& env, ForwardTargets& targets, const gl::Texture& display,
                      float exposure_ev);

}  // namespace candela
// Note: the execute steps keep references to `env` and `targets`; both must outlive the graph's
// execute() (the renderer keeps them on its stack for the whole frame).
