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

#include "effects/knob.hpp"

namespace candela {

class Effect;

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

    // Effect switches (`--effects all|none|LIST`). An effect that is on but not called for by the
    // scene is not planned (see analyze()).
    bool shadows = true;
    bool rsm = false;  // indirect light costs the most; opt-in

    // Render path (`--path`): forward shades every light per fragment; deferred writes a G-buffer
    // and shades it in a tiled compute pass; auto picks deferred from `deferred.auto_lights` lights.
    std::string path = "auto";  // auto|forward|deferred
    // Gating (`render.gating`): an effect the scene does not call for is not run. Off runs every
    // switched-on effect anyway; the image must not change (the gating property test).
    bool gating = true;

    struct Forward {
        bool depth_prepass = false;  // draw depth first, shade with depth test EQUAL
    } forward;
    struct Deferred {
        // Light count from which `--path auto` renders deferred. Measured with
        // `candela bench frame generated:lights:N --path forward|deferred` (README, issue 5 note).
        int auto_lights = 8;  // [1, 100000]
    } deferred;
    struct Shadows {
        int resolution = 1024;          // [64, 8192] texels per side of every shadow view
        std::string filter = "pcss";    // hard|pcf|pcss: one 2x2 hardware PCF tap, pcf_size^2 taps, PCSS
        int pcf_size = 5;               // [1, 15] taps per side of the PCF kernel
        int pcss_blocker_taps = 16;     // [1, 128] blocker-search taps
        int pcss_taps = 32;             // [1, 256] filter taps of PCSS
        float max_radius = 32.0f;       // [1, 64] texels: the largest PCSS search and filter radius
        float normal_bias = 1.0f;       // [0, 16] texels at the receiver, along its normal
        float depth_bias = 0.5f;        // [0, 16] texels at the receiver, towards the light
        float slope_bias = 1.5f;        // [0, 16] polygon-offset factor of the caster pass
        // [0, 4] filter taps r texels away compare against the receiver's plane: r * tan(theta)
        // texels deeper, times this factor (wide PCF/PCSS kernels on tilted receivers)
        float receiver_slope_bias = 1.0f;
        int cascades = 1;               // [1, 4] directional-light cascades
        int max_lights = 16;            // [0, 4096] lights with shadow maps: directional first, then brightest
        float split_lambda = 0.7f;      // [0, 1] cascade splits: 0 uniform, 1 logarithmic
    } shadow;
    struct AreaLights {
        // Raster approximation of each emissive mesh: this many Lambertian pieces, each a light at
        // its piece's centroid with its own shadow map and a PCSS penumbra of the piece's size.
        int samples = 4;  // [1, 64]
    } arealight;
    struct Rsm {
        int resolution = 256;            // [16, 4096] texels per side of each light's RSM view
        int samples = 64;                // [1, 1024] RSM texels gathered per pixel and light
        std::string gather = "half";     // full|half|quarter: resolution of the gather pass
        float radius = 0.15f;            // (0, 1] sampling radius, fraction of the RSM's width
        int max_lights = 4;              // [1, 8] lights with an RSM: directional first, then brightest
    } rsm_knobs;
    struct Debug {
        std::string view = "none";  // none|visibility|ao|indirect: a debug buffer instead of radiance
        int light = 0;  // [0, 1e6] visibility of this light; >= the punctual count: all area lights
    } debug;
    struct AmbientOcclusion {
        float radius = 1.0f;  // (0, 1e9] world units; SSAO and `--raytrace ao` use the same radius
    } ao;
    struct RayTracing {
        std::string jitter = "auto";       // auto|on|off: auto jitters (anti-aliases) path and whitted only
        float whitted_max_roughness = 0.05f;  // [0, 1] smoother surfaces are mirrors in whitted mode
        bool indirect_occlusion = true;       // indirect mode: visibility between bounce points
        bool env_importance = true;           // path/direct: sample environment maps by luminance (MIS)
    } rt;
    struct EnvironmentMap {
        int resolution = 128;  // [16, 1024] face size of the static environment's prefiltered cube
    } environment;
};

// The effect names of `--effects` (shared/DESIGN.md section 4).
const std::vector<std::string>& effect_names();
// Parses "all", "none" or a comma list; throws candela::Error (bad_input) naming an unknown effect.
void apply_effects(RenderSettings& settings, const std::string& list);
// Sets "effect.knob=value"; throws bad_input naming the knob and its range/choices on error.
void apply_knob(RenderSettings& settings, const std::string& assignment);

// Every knob: the base rows (render/) then each registered effect's, in registry order.
const std::vector<Knob>& knobs();
const std::vector<KnobInfo>& knob_infos();

nlohmann::json to_json(const RenderSettings& settings);

}  // namespace candela
