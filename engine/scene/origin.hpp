#pragma once
// Where the scene's float coordinates start (Scene::origin, in the file's frame, in double).
//
// A float keeps about 7 significant digits, so float positions are exact enough only near their
// origin. Two things move Scene::origin:
// - the loader, for a scene far from the file's origin compared with its size (a building on the
//   Earth's surface): the origin goes to the centre of the scene's bounds;
// - the camera, for a scene large compared with what the camera sees close by (a terrain, a
//   city): when the camera stands farther from Scene::origin than kAnchorDistances times its
//   distance to the nearest geometry, the origin goes to the camera (anchor_at_camera), so that
//   the geometry next to it keeps the float steps it would have at the file's origin.
// Either way the roots' translations and the keyframes that move a root are recomputed from the
// file's numbers in double, and everything after them (world matrices, lights, bounds, probe
// grids, the tracer's geometry) follows, because all of it derives from the nodes.
#include <glm/glm.hpp>

#include "scene/scene.hpp"

namespace candela {

// The camera moves Scene::origin when it is farther from it than this many times its distance to
// the nearest geometry (the nearest primitive's world box; from inside a box, its nearest face;
// never less than the near plane). There a float step at the camera is at most 256 * 2^-24
// (1.5e-5) of that distance: 0.015 pixel of a 1000-pixel view with a 60-degree field. The sample
// scenes, the random scenes and the shared models stand well inside it, so they render as the
// file places them.
inline constexpr float kAnchorDistances = 256.0f;

// Moves Scene::origin to `origin` (the file's frame): root translations and root keyframes are
// recomputed in double from the file's numbers, then every world matrix and camera. A posed
// scene (animation, skins, morph targets) must be posed again afterwards (pose_scene).
void move_origin(Scene& scene, const glm::dvec3& origin);

// Moves Scene::origin to `camera`'s position when it stands farther from the current origin than
// kAnchorDistances times its distance to the nearest geometry, and poses the scene again at `time` of `animation`
// (-1: the rest pose); returns whether it moved. `camera` is in the scene's current frame.
bool anchor_at_camera(Scene& scene, const Camera& camera, int animation = -1, float time = 0.0f);

}  // namespace candela
