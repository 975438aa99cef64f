#pragma once
// Which light a scene is rendered with (docs/design.md, "Lighting"). A glTF file
// with no punctual light, no emissive material and no environment would render black; such a
// file is lit by Candela's default rig instead, the same for the raster path, every ray-tracer
// mode and the viewer, because the rig is added to the Scene itself before anything reads it.
//
// The default rig:
// - a neutral procedural sky (`default_sky_image`): a bright, slightly cool zenith, a white
//   horizon and a darker ground, smooth in elevation, made at start-up (no file);
// - one shadow-casting directional key light of kKeyIrradiance W/m^2, coming from above, to the
//   left of and in front of the chosen camera (so the lit side faces the viewer and its shadows
//   fall visibly on the model).
#include <memory>
#include <optional>
#include <string>

#include "image/image.hpp"
#include "scene/scene.hpp"

namespace candela {

enum class LightingMode {
    auto_select,  // the file's own lights, or the default rig when the file has none
    file,         // the file's lights only (a file without any renders black)
    default_rig,  // the default rig only: the file's punctual lights and environment are dropped
};
std::optional<LightingMode> parse_lighting_mode(const std::string& text);
const char* to_string(LightingMode mode);

// What lights the file itself brings: punctual lights placed in the scene, emitters brighter
// than 1 (HDR emission: KHR_materials_emissive_strength) and the environment. Empty when the
// file has none.
std::string own_lighting_summary(const Scene& scene);

struct LightingChoice {
    bool rig = false;    // the default rig was added
    std::string reason;  // one line for `info` and the log
    // `auto` kept the file's own lights and the file has no environment: whether those lights
    // light what the camera sees is measured with the tracer once a GL context exists
    // (rt/view_lighting.hpp: complete_lighting), which may add the default environment.
    bool check_view = false;
    bool environment_added = false;  // complete_lighting added the default environment
};

constexpr float kKeyIrradiance = 2.0f;    // W/m^2, the rig's directional key light
constexpr float kSkyIntensity = 1.0f;     // scale of default_sky_image()

// Applies the policy to a loaded scene. `view` is the camera the image is rendered from: it
// orients the key light. Call before uploading the scene (GpuScene) or building the tracer.
LightingChoice apply_lighting(Scene& scene, LightingMode mode, const Camera& view);

// The rig's sky alone as the scene's environment (no key light): what `auto` adds to a file
// whose own lights leave most of the view unlit.
void add_default_environment(Scene& scene);

// The rig's sky as an equirectangular linear radiance image (width x width/2, RGBA32F), in the
// mapping of shaders/common/math.glsl (row 0 looks up +Y).
std::shared_ptr<const ImageF> default_sky_image(int width = 256);

}  // namespace candela
