#pragma once
// Posing a Scene at a time: glTF node animation (translation, rotation, scale, morph
// weights; LINEAR with slerp for rotations, STEP, CUBICSPLINE), then morph targets and skins.
//
// Everything downstream (GpuScene, the ray tracer's geometry, bounds, culling) reads the posed
// Scene: node `local`/`world` and the primitives' `vertices`. Skinned and morphed primitives are
// posed on the CPU into the node's own space (skinned: inverse(node world) * sum_j w_j * joint
// world_j * inverse bind_j, so the draw's model matrix stays the node's world matrix and the
// result is the glTF one: joint world * inverse bind). One posed geometry feeds the rasterizer
// and the tracer, so both see the same triangles.
#include <string>
#include <vector>

#include "scene/scene.hpp"

namespace candela {

// The value of one sampler at time `t` (seconds): `out` receives `sampler.width` floats. Before
// the first keyframe the first value, after the last the last (glTF clamps). Rotations (`path`
// rotation) are slerped along the shorter arc and normalised, also after CUBICSPLINE. CUBICSPLINE
// scales the tangents by the keyframe interval (glTF 2.0 appendix C).
void sample_animation(const AnimationSampler& sampler, AnimationPath path, float t, float* out);

// The animation by index ("0") or name; throws bad_input naming the available ones if unknown.
int find_animation(const Scene& scene, const std::string& selector);

// Whether a scene has anything that posing changes (animations, skins or morph targets).
bool has_deformation(const Scene& scene);

// A scene's pose at one time, computed without changing the scene.
struct Pose {
    std::vector<glm::mat4> local, world;                // per node
    std::vector<std::vector<float>> weights;            // per node (morph weights)
    std::vector<std::vector<std::vector<Vertex>>> vertices;  // [mesh][primitive]; empty for rigid ones
};

// Evaluates `animation` (-1: none, the rest pose) at `time` seconds.
Pose evaluate_pose(const Scene& scene, int animation, float time);
// Writes a pose into the scene: node local/world/weights, posed vertices and primitive bounds.
void apply_pose(Scene& scene, Pose&& pose);
inline void pose_scene(Scene& scene, int animation, float time) { apply_pose(scene, evaluate_pose(scene, animation, time)); }

// The time interval a frame's shutter is open: centred on `time`, `shutter` frames long at
// `fps` frames per second (camera.shutter; 0: the instant `time`).
struct ShutterInterval {
    float open = 0.0f, close = 0.0f;
    bool instant() const { return !(close > open); }
};
ShutterInterval shutter_interval(float time, float shutter, float fps);

}  // namespace candela
