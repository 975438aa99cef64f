#pragma once
// RenderSettings: every effect switch and knob, plain data with defaults (Filament's Options
// style). Knobs are addressed as "effect.knob" by `--set`, the viewer and the stats JSON; each has
// a unit and a valid range, and a value outside it is rejected, never clamped silently.
#include <any>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "render/knob.hpp"

namespace candela {

class Effect;

enum class RenderPath { automatic, forward, deferred };
inline constexpr ChoiceName<RenderPath> kRenderPaths[] = {
    {"auto", RenderPath::automatic}, {"forward", RenderPath::forward}, {"deferred", RenderPath::deferred}};
// A debug buffer instead of radiance: a light's visibility, the SSAO buffer, RSM's indirect light.
enum class DebugView { none, visibility, ao, indirect };
inline constexpr ChoiceName<DebugView> kDebugViews[] = {
    {"none", DebugView::none}, {"visibility", DebugView::visibility}, {"ao", DebugView::ao}, {"indirect", DebugView::indirect}};
enum class RtJitter { automatic, on, off };
inline constexpr ChoiceName<RtJitter> kRtJitters[] = {{"auto", RtJitter::automatic}, {"on", RtJitter::on}, {"off", RtJitter::off}};

// One registered effect's switch and options (engine/effects/<name>/: the options struct).
struct EffectSlot {
    const Effect* effect = nullptr;
    bool on = true;
    std::any options;
};
// A slot per registered effect, in registry order, with each effect's defaults.
std::vector<EffectSlot> default_effect_slots();

struct RenderSettings {
    // The effect modules' switches and options (engine/effects/registry.cpp).
    std::vector<EffectSlot> effects = default_effect_slots();
    // This effect's options, by its options type: settings.get<SsaoOptions>().samples.
    template <class Options>
    Options& get() {
        for (EffectSlot& slot : effects)
            if (auto* o = std::any_cast<Options>(&slot.options)) return *o;
        throw Error(ExitCode::internal, "RenderSettings: no registered effect has these options");
    }
    template <class Options>
    const Options& get() const {
        return const_cast<RenderSettings*>(this)->get<Options>();
    }
    // The switch of the effect `name` (`--effects`); throws internal for an unknown name.
    bool on(std::string_view name) const;
    void set_on(std::string_view name, bool on);

    // Render path (`--path`): forward shades every light per fragment; deferred writes a G-buffer
    // and shades it in a tiled compute pass; auto picks deferred from `deferred.auto_lights` lights.
    RenderPath path = RenderPath::automatic;
    // Gating (`render.gating`): an effect the scene does not call for is not run. Off runs every
    // switched-on effect anyway; the image must not change (the gating property test).
    bool gating = true;
    // The layers of the glTF material extensions (`render.material_layers`): clearcoat, sheen,
    // anisotropy, iridescence, unlit and the extensions' textures. Off shades every material with
    // its base BRDF only (the cheaper programs); the tracer always shades them.
    bool material_layers = true;

    struct Forward {
        bool depth_prepass = false;  // draw depth first, shade with depth test EQUAL
        bool light_tiles = true;     // cull lights with a range per 16x16 tile (the image is the same)
    } forward;
    struct Lights {
        // Point and spot lights without a range (the glTF default) reach as far as their light
        // off a white Lambertian surface stays above their share of this fraction of one 8-bit
        // display step (exposure 0, at the display's steepest: kDisplayQuantum), shared by all
        // of them: their 1/d^2 less its value there, so that it falls to exactly 0 at the reach,
        // and all the cuts together change a white Lambertian surface's light by at most that
        // fraction (gpu_scene.hpp, light_cutoff_distance). The tile culling of both paths skips
        // them beyond. 0: no cutoff, unbounded reach.
        float cutoff = 0.5f;  // [0, 1e6]
    } lights;
    struct Deferred {
        // Light count from which `--path auto` renders deferred. Measured with
        // `candela bench frame generated:lights:N --path forward|deferred` (docs/cli.md, render paths).
        int auto_lights = 8;  // [1, 100000]
    } deferred;
    struct Debug {
        DebugView view = DebugView::none;
        int light = 0;  // [0, 1e6] visibility of this light; >= the punctual count: all area lights
    } debug;
    struct AmbientOcclusion {
        float radius = 1.0f;  // (0, 1e9] world units; SSAO and `--raytrace ao` use the same radius
    } ao;
    struct RayTracing {
        RtJitter jitter = RtJitter::automatic;  // auto = on: the box-filtered pixel average, every mode
        float whitted_max_roughness = 0.05f;  // [0, 1] smoother surfaces are mirrors in whitted mode
        bool indirect_occlusion = true;       // indirect mode: visibility between bounce points
        bool env_importance = true;           // path/direct: sample environment maps by luminance (MIS)
        // Motion blur: the tracer poses the scene and rebuilds its geometry this many times per
        // render, at stratified random times in the shutter (each sample pass takes one time);
        // 0: one time per sample (exact per pixel). Cost: one pose + BVH build per slice.
        int shutter_slices = 0;  // [0, 1 << 24]
    } rt;
    struct EnvironmentMap {
        int resolution = 128;  // [16, 1024] face size of the static environment's prefiltered cube
    } environment;
    // The camera's thin lens (depth of field). -1: the camera's own (glTF camera extras), which
    // default to a pinhole; otherwise these override every camera.
    struct Lens {
        float aperture = -1.0f;        // [-1, 1e9] lens radius in scene units; 0: pinhole
        float focus_distance = -1.0f;  // [-1, 1e9] distance in focus along the view axis; 0: auto
        // Motion blur: the shutter stays open this fraction of a frame, centred on the
        // frame's time (animation.hpp shutter_interval); 0: off. fps sets the frame length.
        float shutter = 0.0f;  // [0, 1]
        float fps = 30.0f;     // [1, 1000] frames per second (render --fps sets it too)
    } camera;
};

struct Camera;
// `camera` with the settings' lens applied (camera.aperture / camera.focus_distance >= 0 override
// the camera's own).
Camera with_lens(Camera camera, const RenderSettings& settings);

// The effect names of `--effects` (docs/cli.md).
const std::vector<std::string>& effect_names();
// Parses "all", "none" or a comma list; throws candela::Error (bad_input) naming an unknown effect.
void apply_effects(RenderSettings& settings, const std::string& list);
// Sets "effect.knob=value"; throws bad_input naming the knob and its range/choices on error.
void apply_knob(RenderSettings& settings, const std::string& assignment);
// The --set list of a command, in order, then what the given knobs imply (Effect::complete_knobs).
void apply_knobs(RenderSettings& settings, const std::vector<std::string>& assignments);

// Every knob: the base rows (render/) then each registered effect's, in registry order.
const std::vector<Knob>& knobs();
const std::vector<KnobInfo>& knob_infos();

nlohmann::json to_json(const RenderSettings& settings);

}  // namespace candela
