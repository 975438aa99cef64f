#pragma once
// RenderSettings: every effect switch and knob, plain data with defaults (Filament's Options
// style). Knobs are addressed as "effect.knob" by `--set`, the viewer and the stats JSON; each has
// a unit and a valid range, and a value outside it is rejected, never clamped silently.
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

namespace candela {

struct RenderSettings {
    // Effect switches (`--effects all|none|LIST`). An effect that is on but not called for by the
    // scene is not planned (see analyze()).
    bool shadows = true;
    bool ssao = true;
    bool rsm = false;  // indirect light costs the most; opt-in
    bool transparency = true;
    bool reflections = true;

    struct Forward {
        bool depth_prepass = false;  // draw depth first, shade with depth test EQUAL
    } forward;
    struct Transparency {
        std::string sort = "object";  // object: by bounds centre (triangle sort: transparency issue)
    } transparency_knobs;
    struct AreaLights {
        int subdivisions = 3;  // [1, 16] emissive triangle split into n^2 Lambertian patches
        int max_patches = 256; // [1, 4096] total patches over the scene
    } area;
    struct AmbientOcclusion {
        float radius = 1.0f;  // (0, 1e9] world units; SSAO and `--raytrace ao` use the same radius
    } ao;
    struct RayTracing {
        std::string jitter = "auto";       // auto|on|off: auto jitters (anti-aliases) path and whitted only
        float whitted_max_roughness = 0.05f;  // [0, 1] smoother surfaces are mirrors in whitted mode
        bool indirect_occlusion = true;       // indirect mode: visibility between bounce points
        bool env_importance = true;           // path/direct: sample environment maps by luminance (MIS)
    } rt;
    struct Reflections {
        float max_roughness = 0.3f;  // [0, 1] metallic surfaces rougher than this need no reflection pass
    } reflections_knobs;
};

// The effect names of `--effects` (shared/DESIGN.md section 4).
const std::vector<std::string>& effect_names();
// Parses "all", "none" or a comma list; throws candela::Error (bad_input) naming an unknown effect.
void apply_effects(RenderSettings& settings, const std::string& list);
// Sets "effect.knob=value"; throws bad_input naming the knob and its range/choices on error.
void apply_knob(RenderSettings& settings, const std::string& assignment);

struct KnobInfo {
    std::string name;   // "area.subdivisions"
    std::string type;   // "bool", "int", "float", "choice"
    std::string range;  // "[1, 16]", "object|triangle", ...
    std::string help;
};
const std::vector<KnobInfo>& knob_infos();

nlohmann::json to_json(const RenderSettings& settings);

}  // namespace candela
