#pragma once
// Shadow views of a frame (one per shadow-map layer), in the layout of shaders/lighting/
// shadows.glsl. Directional lights: orthographic maps fitted to the part of the scene the camera
// sees (its frustum, split into cascades, clipped to the scene bounds) and texel-snapped. Spot
// lights: one perspective map over the cone. Point lights and area-light pieces: six 90-degree
// faces, widened by a guard band so that filter taps near a face border stay inside the face.
// All maps are reversed-Z float depth: perspective maps use an infinite far plane, so precision
// is spent where 1/z needs it and the near plane can be small (1e-3 of the scene's extent as
// seen from the light) without losing the far end.
#include <vector>

#include <glm/glm.hpp>

#include "effects/shadows/shadows_data.h"
#include "render/gpu_scene.hpp"
#include "scene/scene.hpp"

namespace candela {

struct ShadowsOptions;

// A shadow view as the GLSL reads it (effects/shadows/shadows_data.h).
using ShadowViewData = gpu::ShadowView;

struct ShadowViews {
    std::vector<ShadowViewData> views;  // index = layer
    std::vector<int> light;             // the light of each view
    std::vector<bool> skip;             // faces behind a one-sided emitter: nothing to render
    std::vector<float> texel_world;     // ortho views: world size of a texel (diagnostics, tests)
};

// The frame's views for every light that has shadow views assigned (GpuScene::update_lights).
ShadowViews build_shadow_views(const GpuScene& gpu, const Bounds& scene_bounds, const Camera& camera, float aspect,
                               const ShadowsOptions& options);

// An orthographic view of a directional light over the whole scene (what a reflective shadow map
// needs: bounce surfaces outside the camera's view light what is in it).
ShadowViewData directional_scene_view(const glm::vec3& direction, const Bounds& scene_bounds, int resolution);

// Cascade split depths (Zhang et al. 2006, practical split scheme): cascades+1 values from near
// to far, lambda blending logarithmic (1) and uniform (0) splits.
std::vector<float> cascade_splits(float near, float far, int cascades, float lambda);

}  // namespace candela
