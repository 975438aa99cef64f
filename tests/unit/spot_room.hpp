#pragma once
// A closed grey room lit by one spot, for the GI tests against the tracer (the probes' light off
// metal and through glass): 4 m x 3 m x 4 m (rough, albedo 0.6) around the origin of the floor,
// its six quads facing in, a spot pointing down from `spot_at` (cones `inner`, `outer`, 20 W/sr)
// and a camera at `eye` looking at `target`.
#include <glm/gtc/matrix_transform.hpp>

#include "scene/generate.hpp"
#include "scene/mesh_utils.hpp"
#include "scene/scene.hpp"

namespace candela::test {

inline Scene spot_room(const char* source, glm::vec3 spot_at, float inner, float outer, glm::vec3 eye, glm::vec3 target) {
    Scene scene;
    scene.source = source;
    scene.materials.push_back(lambert_material("room", glm::vec3(0.6f)));
    Primitive room;
    room.material = 0;
    // append_quad faces cross(eu, ev).
    append_quad(room, {-2, 0, -2}, {0, 0, 4}, {4, 0, 0});  // floor, +y
    append_quad(room, {-2, 3, -2}, {4, 0, 0}, {0, 0, 4});  // ceiling, -y
    append_quad(room, {-2, 0, -2}, {4, 0, 0}, {0, 3, 0});  // z = -2, +z
    append_quad(room, {-2, 0, 2}, {0, 3, 0}, {4, 0, 0});   // z = 2, -z
    append_quad(room, {-2, 0, -2}, {0, 3, 0}, {0, 0, 4});  // x = -2, +x
    append_quad(room, {2, 0, -2}, {0, 0, 4}, {0, 3, 0});   // x = 2, -x
    add_mesh_node(scene, "room", std::move(room));
    Light spot;
    spot.name = "spot";
    spot.type = LightType::spot;
    spot.intensity = 20.0f;
    spot.inner_cone = inner;
    spot.outer_cone = outer;
    scene.lights.push_back(spot);
    Node light;
    light.name = "spot";
    light.light = 0;
    // A node's -z is where the light points: down (-y).
    light.local = glm::translate(glm::mat4(1.0f), spot_at) * glm::rotate(glm::mat4(1.0f), -1.5707963f, glm::vec3(1, 0, 0));
    light.has_matrix = true;
    scene.nodes.push_back(light);
    scene.roots.push_back(static_cast<int>(scene.nodes.size()) - 1);
    Camera cam;
    cam.name = "view";
    cam.yfov = 1.2f;
    cam.znear = 0.05f;
    cam.world = glm::inverse(glm::lookAt(eye, target, glm::vec3(0, 1, 0)));
    scene.cameras.push_back(cam);
    return scene;
}

}  // namespace candela::test
