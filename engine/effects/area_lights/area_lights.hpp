#pragma once
// The rasterizer's area lights (engine/effects/area_lights/). Each emissive primitive is split
// into arealight.samples pieces (render/gpu_scene.hpp: AreaPiece), each a light at its centroid
// with its own shadow map. How the emitters shade (arealight.method):
// - ltc (default): every emissive triangle is a polygon light, integrated exactly over the
//   Lambert lobe and a linearly transformed cosine fitted to Candela's GGX lobe (Heitz et al.
//   2016; the table: ltc.hpp, fitted by effects/area_lights/ltc_fit). The pieces only cast shadows, applied
//   as the ratio of their shadowed to unshadowed estimates (Heitz, Hill & McGuire 2018), so an
//   unoccluded point gets exactly the LTC value. A textured emitter shades with its texture's
//   average over each triangle. What the fitted lobe misses (GGX's tails near the horizon, its
//   shape at grazing views) is added back as a residual measured on cells
//   (arealight.residual: 3x3 cells of each polygon; area_lights_shading.glsl).
// - pieces: the pieces themselves shade, as Lambertian point lights (the old approximation,
//   kept for comparison in `bench accuracy`).
// It has no pass of its own: the lighting passes read the light buffer and the polygons. It is
// not switchable, and it runs when the emitters' light matters: before planning, the tracer
// measures what their light adds to the view (rt/view_light.hpp, measure_emitter_light); when
// that changes the displayed image by less than arealight.negligible (labels, indicator LEDs),
// the emitters are drawn as emission only, no light pieces, no polygons, and `info` says so.
#include <glm/glm.hpp>

#include <vector>

#include "effects/area_lights/area_lights_data.h"
#include "render/effect.hpp"
#include "render/gpu_scene.hpp"

namespace candela {

enum class AreaLightMethod { ltc, pieces };
inline constexpr ChoiceName<AreaLightMethod> kAreaLightMethods[] = {{"ltc", AreaLightMethod::ltc}, {"pieces", AreaLightMethod::pieces}};

struct AreaLightsOptions {
    int samples = 4;  // [1, 64] shadowed pieces per emissive primitive
    AreaLightMethod method = AreaLightMethod::ltc;
    bool residual = true;  // ltc: add the lobe's part the fit misses, measured on cells of each polygon
    // ltc: a polygon seen from farther than this many of its bounding radii, and narrower than a
    // quarter of the specular lobe's width, is shaded as a point emitter (its radiance times its
    // solid angle through the BRDF) instead of by the LTC integrals: the irradiance of a uniform
    // disk of angular radius t differs from the point's by a factor 1/(1 + t^2), 1.6 % at 8.
    // [0, 64]; 0: every polygon by LTC.
    float far_field = 8.0f;
    // The emitters light the scene when their measured light changes the displayed image by at
    // least this much (99th percentile over 4x4 blocks of the largest channel's difference,
    // display values in [0, 1], exposure 0) or is at least 2 % of the direct light on the view's
    // surfaces (a measure no exposure changes); else they are emission only. Half the goldens'
    // per-pixel tolerance (2/255). 0: emitters are always lights.
    float negligible = 1.0f / 255.0f;
};

const Effect& area_lights_effect();

// The scene's emissive draws split into `samples` pieces each, grouped by emitter (area_pieces.cpp):
// the LightSetup::split_emitters this effect gives the light buffer.
std::vector<AreaPiece> area_light_pieces(const Scene& scene, const GpuScene& gpu, int samples);

struct Scene;
class GpuScene;

// One emissive triangle, or a quad of two coplanar ones, as the lighting passes read it (area_lights_data.h).
using PolygonLightGpu = gpu::PolygonLight;
// The polygon lights of the scene's emissive primitives (pairs of coplanar triangles of equal
// radiance merged into convex quads), grouped by emitter in the light
// buffer's piece order (GpuScene::update_lights with `samples` pieces per primitive).
std::vector<PolygonLightGpu> polygon_lights(const Scene& scene, const GpuScene& gpu, int samples);

}  // namespace candela
