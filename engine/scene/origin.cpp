#include "scene/origin.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/gtc/matrix_transform.hpp>

#include "scene/animation.hpp"

namespace candela {
namespace {

// Roots and root keyframes without a recorded placement (a scene built in code, or roots added
// after loading) are taken as they are: their translation plus the current origin, and their
// sampler as the file's. Placements of nodes that are no longer roots are dropped.
void record_placement(Scene& scene) {
    std::vector<bool> root(scene.nodes.size(), false), placed(scene.nodes.size(), false);
    for (int r : scene.roots)
        if (r >= 0 && static_cast<size_t>(r) < root.size()) root[static_cast<size_t>(r)] = true;
    std::erase_if(scene.root_placements, [&](const Scene::RootPlacement& p) {
        return p.node < 0 || static_cast<size_t>(p.node) >= root.size() || !root[static_cast<size_t>(p.node)];
    });
    for (const Scene::RootPlacement& p : scene.root_placements) placed[static_cast<size_t>(p.node)] = true;
    for (int r : scene.roots) {
        if (r < 0 || static_cast<size_t>(r) >= scene.nodes.size() || placed[static_cast<size_t>(r)]) continue;
        placed[static_cast<size_t>(r)] = true;
        const Node& node = scene.nodes[static_cast<size_t>(r)];
        const glm::vec3 t = node.has_matrix ? glm::vec3(node.rest_local.value_or(node.local)[3]) : node.translation;
        scene.root_placements.push_back({r, scene.origin + glm::dvec3(t)});
    }
    for (size_t a = 0; a < scene.animations.size(); ++a) {
        const Animation& anim = scene.animations[a];
        for (size_t c = 0; c < anim.channels.size(); ++c) {
            const AnimationChannel& ch = anim.channels[c];
            if (ch.path != AnimationPath::translation || ch.node < 0 || static_cast<size_t>(ch.node) >= root.size() ||
                !root[static_cast<size_t>(ch.node)] || ch.sampler < 0 || static_cast<size_t>(ch.sampler) >= anim.samplers.size())
                continue;
            const bool tracked = std::any_of(scene.root_tracks.begin(), scene.root_tracks.end(), [&](const Scene::RootTrack& t) {
                return t.animation == static_cast<int>(a) && t.channel == static_cast<int>(c);
            });
            if (!tracked) scene.root_tracks.push_back({static_cast<int>(a), static_cast<int>(c), ch.sampler, -1});
        }
    }
}

}  // namespace

void move_origin(Scene& scene, const glm::dvec3& origin) {
    record_placement(scene);
    for (const Scene::RootPlacement& rp : scene.root_placements) {
        Node& node = scene.nodes[static_cast<size_t>(rp.node)];
        const glm::vec3 t(rp.translation - origin);
        if (node.has_matrix) {
            node.local[3] = glm::vec4(t, 1.0f);
            if (node.rest_local) (*node.rest_local)[3] = glm::vec4(t, 1.0f);
        } else {
            node.translation = t;
            const glm::mat4 trs = glm::translate(glm::mat4(1.0f), t) * glm::mat4_cast(node.rotation) * glm::scale(glm::mat4(1.0f), node.scale);
            node.local = trs;
            if (node.rest_local) node.rest_local = trs;
        }
    }
    // Keyframes that move a root: a copy of the file's sampler whose values (not a cubic spline's
    // tangents, which are differences) lose the origin, subtracted in double.
    for (Scene::RootTrack& track : scene.root_tracks) {
        Animation& anim = scene.animations[static_cast<size_t>(track.animation)];
        AnimationSampler moved = anim.samplers[static_cast<size_t>(track.file_sampler)];
        const bool cubic = moved.interpolation == Interpolation::cubic_spline;
        const size_t stride = cubic ? 9 : 3, first = cubic ? 3 : 0;
        for (size_t k = first; k + 3 <= moved.values.size(); k += stride)
            for (int a = 0; a < 3; ++a) {
                float& v = moved.values[k + static_cast<size_t>(a)];
                v = static_cast<float>(static_cast<double>(v) - origin[a]);
            }
        if (track.moved_sampler < 0) {
            anim.samplers.push_back(std::move(moved));
            track.moved_sampler = static_cast<int>(anim.samplers.size()) - 1;
        } else {
            anim.samplers[static_cast<size_t>(track.moved_sampler)] = std::move(moved);
        }
        anim.channels[static_cast<size_t>(track.channel)].sampler = track.moved_sampler;
    }
    // Cameras that no node places (a framing or orbit camera added in code) move with the scene.
    const glm::vec3 shift(origin - scene.origin);
    for (Camera& camera : scene.cameras)
        if (camera.node < 0) camera.world[3] -= glm::vec4(shift, 0.0f);
    scene.origin = origin;
    scene.update_world_transforms();
}

namespace {

// How far the camera is from what it may see close by: the distance to the nearest primitive's
// world box, or from inside a box to its nearest face (a room's wall, a terrain's top), never
// less than the near plane (an orthographic camera: its half height).
float nearest_geometry(const Scene& scene, const Camera& camera, const glm::vec3& eye) {
    float nearest = std::numeric_limits<float>::max();
    for (const Node& node : scene.nodes) {
        if (node.mesh < 0 || static_cast<size_t>(node.mesh) >= scene.meshes.size()) continue;
        for (const Primitive& prim : scene.meshes[static_cast<size_t>(node.mesh)].primitives) {
            if (prim.bounds.empty()) continue;
            Bounds box;
            for (int c = 0; c < 8; ++c) {
                const glm::vec3 corner((c & 1) ? prim.bounds.max.x : prim.bounds.min.x, (c & 2) ? prim.bounds.max.y : prim.bounds.min.y,
                                       (c & 4) ? prim.bounds.max.z : prim.bounds.min.z);
                box.extend(glm::vec3(node.world * glm::vec4(corner, 1.0f)));
            }
            const glm::vec3 outside = glm::max(glm::max(box.min - eye, eye - box.max), glm::vec3(0.0f));
            const float d = outside == glm::vec3(0.0f)
                                ? std::min({eye.x - box.min.x, box.max.x - eye.x, eye.y - box.min.y, box.max.y - eye.y, eye.z - box.min.z, box.max.z - eye.z})
                                : glm::length(outside);
            nearest = std::min(nearest, d);
        }
    }
    const float lens = camera.orthographic ? std::max(camera.znear, camera.ymag) : camera.znear;
    return std::max(nearest == std::numeric_limits<float>::max() ? 0.0f : nearest, lens);
}

}  // namespace

bool anchor_at_camera(Scene& scene, const Camera& camera, int animation, float time) {
    const glm::vec3 eye(camera.world[3]);
    const float far = glm::length(eye);
    if (!std::isfinite(far)) return false;
    // Cheap first: the near plane is a lower bound of the distance to what the camera sees.
    const float lens = camera.orthographic ? std::max(camera.znear, camera.ymag) : camera.znear;
    if (!(far > kAnchorDistances * lens)) return false;
    if (!(far > kAnchorDistances * nearest_geometry(scene, camera, eye))) return false;
    move_origin(scene, scene.origin + glm::dvec3(eye));
    pose_scene(scene, animation, time);
    return true;
}

}  // namespace candela
