#pragma once
// Shadow maps (engine/effects/shadows/): one depth layer per shadow view (shadow_views.hpp) of
// every shadowed light, filtered by the lighting (shadows_shading.glsl) with a hard 2x2 PCF tap,
// a PCF kernel or PCSS.
#include "render/effect.hpp"
#include "effects/shadows/shadow_views.hpp"

namespace candela {

enum class ShadowFilter { hard = 1, pcf = 2, pcss = 3 };  // the values of ShadowsData::filter_mode
inline constexpr ChoiceName<ShadowFilter> kShadowFilters[] = {
    {"hard", ShadowFilter::hard}, {"pcf", ShadowFilter::pcf}, {"pcss", ShadowFilter::pcss}};

struct ShadowsOptions {
    int resolution = 1024;                      // [64, 8192] texels per side of a full-resolution shadow view
    ShadowFilter filter = ShadowFilter::pcss;   // one 2x2 hardware PCF tap, pcf_size^2 taps, PCSS
    int pcf_size = 5;                           // [1, 15] taps per side of the PCF kernel
    int pcss_blocker_taps = 16;                 // [1, 128] blocker-search taps
    int pcss_taps = 32;                         // [1, 256] filter taps of PCSS
    float max_radius = 32.0f;                   // [1, 64] texels: the largest PCSS search and filter radius
    float normal_bias = 1.0f;                   // [0, 16] texels at the receiver, along its normal
    float depth_bias = 0.5f;                    // [0, 16] texels at the receiver, towards the light
    float slope_bias = 1.5f;                    // [0, 16] polygon-offset factor of the caster pass
    // [0, 4] filter taps r texels away compare against the receiver's plane: r * tan(theta)
    // texels deeper, times this factor (wide PCF/PCSS kernels on tilted receivers)
    float receiver_slope_bias = 1.0f;
    int cascades = 1;                           // [1, 4] directional-light cascades
    int max_lights = 16;                        // [0, 4096] lights with shadow maps: directional first, then by what they add to the view
    // [16, 16384] MiB of shadow maps at most, shared by the shadowed lights (render/shadow_atlas.hpp):
    // lower-priority lights get smaller tiles, and beyond the smallest none
    int budget_mb = 512;
    float split_lambda = 0.7f;                  // [0, 1] cascade splits: 0 uniform, 1 logarithmic
    // Keep a view's depth from an earlier frame while its view, the scene's pose and the caster
    // settings are unchanged (a still light under a moving camera: only cascades follow the camera).
    bool cache = true;
};

const Effect& shadows_effect();

// The effect's state in a renderer (Renderer::effect_runtime<ShadowsRuntime>()).
class ShadowsRuntime final : public EffectRuntime {
public:
    // This frame's shadow views (empty when the shadow pass does not run).
    const ShadowViews& views() const { return cpu_; }
    // The nearest-texel sampler of the maps (other effects read their own light views with it).
    const gl::Sampler& raw_sampler() const { return raw_; }
    // Shadow views drawn in the last frame (the others kept their cached depth).
    int layers_drawn() const { return layers_drawn_; }

    void prepare(const FramePrep& prep) override;
    void begin_graph(FrameGraph& graph) override;
    // The pass shadow_maps: every shadow view whose cached depth is stale.
    void add_maps(FrameGraph& graph, const PassEnv& env);
    void read_shading_inputs(FrameGraph::Builder& b) const override;
    void bind_shading_inputs(const PassEnv& env, FrameGraph::Context* ctx) const override;
    std::vector<std::string> shading_defines() const override { return defines_; }

private:
    ShadowsOptions options_;
    bool on_ = false;
    gl::Texture array_;                      // DEPTH32F, one layer per view
    std::vector<gl::Framebuffer> layer_fbos_;
    gl::Buffer views_;                       // ShadowViewData[]
    GLsizeiptr views_bytes_ = 0;
    ShadowViews cpu_;
    gl::Sampler compare_, raw_;
    int resolution_ = 0, layers_ = 0;
    gl::Buffer block_;
    std::vector<std::string> defines_;  // shading_defines: from the block's filter mode
    FrameGraph::ResourceId maps_ = -1;
    // What each layer of array_ holds (shadows.cache): the view, light and skip it was drawn with.
    struct DrawnLayer {  // what a view's tile holds
        glm::mat4 view_proj{0.0f};
        ShadowTile tile;
        int light = -1;
        bool skip = false;
        bool valid = false;
    };
    std::vector<DrawnLayer> drawn_;
    const GpuScene* drawn_gpu_ = nullptr;
    std::uint64_t drawn_pose_ = 0;
    float drawn_slope_bias_ = -1.0f;
    int layers_drawn_ = 0;
};

}  // namespace candela
