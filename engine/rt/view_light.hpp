#pragma once
// What the camera sees and how the scene's lights light it, measured with the tracer on a small
// image at the render's camera and aspect: the planner's input for how much of the image is
// indirect light (the GI effect) and for whether a file's own lights leave the view unlit
// (`--lighting auto`, scene/lighting.hpp).
//
// Tiny renders over one BVH:
// - `hits`: per pixel, the share of camera rays that see a passive surface, an emitter or nothing.
//   Emitters are known by what the ray hits (any emission towards the camera), never by
//   brightness;
// - `path` truncated after one, two and three vertices, with Options::camera_sees_emission off:
//   the direct light the seen surfaces reflect (punctual lights, emitters, environment), then
//   its first and second bounce, every BRDF lobe, without the emission or sky the camera sees
//   itself (the same random numbers in the three, so their differences are exact);
// - `ao` with a radius far beyond the scene: how much of the seen surfaces' hemisphere is open
//   to the sky.
// The sums run over the passive share of each pixel, so an emitter or the background in view
// neither counts as lit surface nor hides one.
#include <memory>
#include <string>

#include "scene/scene.hpp"

namespace candela {

namespace rt {
class RtScene;
}

class GpuScene;
class ShaderLibrary;

struct ViewLight {
    int width = 0, height = 0, spp = 0;
    // Shares of the image's camera rays (they add up to 1).
    double passive_share = 0.0, emitter_share = 0.0, background_share = 0.0;
    // Means over the image of the light the seen surfaces reflect, each pixel weighted by the
    // diffuse part of its surface ((1 - metallic)(1 - transmission): a mirror or glass shows its
    // surroundings, the reflection effect's work): D direct, B1 its first bounce, B2 its second,
    // B3 its third.
    double direct_mean = 0.0, bounce_mean = 0.0, second_bounce_mean = 0.0, third_bounce_mean = 0.0;
    // B1 / D and its standard error (a ratio estimator over the pixels; it counts the spread of
    // the light across the image as well as the sampling noise, so it errs large). 0 when D is 0.
    double ratio = 0.0, ratio_stderr = 0.0;
    // r = B3 / B2 (B2 / B1 without a third bounce; at most 0.95): what each bounce after the
    // second returns of the one before.
    double per_bounce = 0.0;
    double albedo_bound = 1.0;  // scattering_albedo_bound(scene): per_bounce's upper limit
    // The indirect share of the seen surfaces' light, I / (D + I) with I = B1 + B2 / (1 - r).
    double indirect_share = 0.0;
    // Cosine-weighted share of the seen surfaces' hemisphere that no geometry blocks: 0 in a
    // closed room, where no sky can reach.
    double sky_visibility = 0.0;
    int surface_pixels = 0;  // pixels whose camera rays mostly see passive surfaces
    int lit_pixels = 0;      // of those, pixels with direct light
    // Of the surface pixels, the share whose light (D + B1) is below kUnlitLevel of the typical
    // directly lit level (the median of the lit pixels; without any, every pixel counts as unlit).
    double unlit_share = 0.0;
    // Of the surface pixels that are mostly diffuse (glass and mirrors show what lies beyond them
    // through later vertices), the share that direct light leaves below kUnlitLevel of the typical
    // lit level and that their first three bounces make visible (at least kVisibleIndirect in
    // display values, exposure 0): what goes black without indirect light,
    // however small the indirect share of the whole image (a wall that only the lit floor lights).
    double indirect_only_share = 0.0;
    double ms = 0.0;  // wall time (BVH, programs, the three renders)
    std::string text() const;
};

// A pixel whose light is below this fraction of the typical directly lit pixel's looks black
// beside it (about 38/255 in sRGB where the lit level is display white).
constexpr double kUnlitLevel = 0.02;
// A display value (exposure 0) that reads as lit beside black: about 13/255.
constexpr double kVisibleIndirect = 0.05;
// About this many pixels at the given aspect (`pixels`, by default), `spp` samples each.
constexpr int kViewLightPixels = 1536;

// Throws candela::Error if the tracer cannot be built (internal) or the scene has no triangles
// (bad_input: nothing to trace).
// The largest albedo with which a surface of the scene scatters light (every material, and the
// glTF default material where a primitive has none): the share of a bounce the next can return.
double scattering_albedo_bound(const Scene& scene);
// `shared` (optional, in and out): the tracer geometry of an earlier measurement of this scene
// (rt::RayTracer::shared_scene), used and then kept there, so that a caller measuring several
// times builds the BVH once.
ViewLight measure_view_light(const ShaderLibrary& shaders, const Scene& scene, GpuScene& gpu, const Camera& camera, float aspect,
                             int spp = 8, int pixels = kViewLightPixels, std::shared_ptr<rt::RtScene>* shared = nullptr);

// Caustics, the light the raster cannot carry: the share of the light the surfaces in view
// reflect that reaches them through glass or off a mirror (rt::Options::caustics_only: the first
// diffuse or glossy surface on a camera ray, then only glass or mirrors, then a light). The raster
// draws none of it, so it is what a raster image misses there. Found by the tracer's BRDF
// sampling (and next-event estimation at a mirror), so it is noisy at few samples: the share is
// the mean of 4 independent batches and stderr_share its standard error from their spread.
struct Caustics {
    int width = 0, height = 0, spp = 0;
    double share = 0.0, stderr_share = 0.0;
    // Mean |display difference| over 4x4 blocks (exposure 0) between the tracer's image and the
    // same less its caustics: the error-budget's measure of what a raster image without caustics
    // misses at least (--error-budget takes it as a floor of every raster candidate's error).
    double display_error = 0.0;
    double ms = 0.0;
    std::string text() const;
};
// Whether the scene has anything a caustic could pass: a transmissive material or a metal
// smoother than rt::kCausticMirrorRoughness.
bool can_have_caustics(const Scene& scene);
// `shared`: as measure_view_light's.
Caustics measure_caustics(const ShaderLibrary& shaders, const Scene& scene, GpuScene& gpu, const Camera& camera, float aspect,
                          int spp = 32, int pixels = kViewLightPixels, std::shared_ptr<rt::RtScene>* shared = nullptr);

// What the emissive surfaces' light adds to the image where it falls on other surfaces: the
// light the raster's area lights carry (engine/effects/area_lights/), measured to decide whether
// they are worth their cost. Two `direct` renders (the seen surfaces' direct light, without what
// the camera sees itself): every light, and the emitters' alone (rt::Options::emitters_only).
// The image without the emitters' light is the first less the second; the measure is the display
// difference between the two over 4x4 blocks (block_agreement, exposure 0). The direct light is
// less than the image's light, so the display differences are those of a darker image: larger
// (sRGB is steepest near black), a bound that errs towards keeping the lights. The emitters' own
// emission seen through glass or in a mirror counts too, although the raster shows it without the
// area lights: that errs the same way.
struct EmitterLight {
    int width = 0, height = 0, spp = 0;
    double display_mean = 0.0;  // mean |display difference| over 4x4 blocks and channels
    double display_p99 = 0.0;   // 99th percentile over blocks of the largest channel difference
    double share = 0.0;         // the emitters' share of the direct light on the seen surfaces
    double ms = 0.0;
    std::string text() const;
};
// `shared`: as measure_view_light's.
EmitterLight measure_emitter_light(const ShaderLibrary& shaders, const Scene& scene, GpuScene& gpu, const Camera& camera,
                                   float aspect, int spp = 16, int pixels = kViewLightPixels,
                                   std::shared_ptr<rt::RtScene>* shared = nullptr);

}  // namespace candela
