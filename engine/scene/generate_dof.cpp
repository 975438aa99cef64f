// generated:dof, the depth-of-field scene: an in-focus subject, a near and a far
// out-of-focus object, a checkered floor and back wall, one directional light and a thin-lens
// camera focused on the subject. Every object is made of two materials in a checker or in bands,
// so that blurred edges are high-contrast everywhere on screen.
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

#include "scene/generate.hpp"
#include "scene/mesh_utils.hpp"

namespace candela {
Scene make_dof_scene() {
    Scene scene;
    scene.source = "generated:dof";
    enum { white, dark, red, cream, yellow, blue, green, pale };
    scene.materials = {lambert_material("white", glm::vec3(0.8f)),         lambert_material("dark", glm::vec3(0.05f)),
                       lambert_material("red", {0.8f, 0.08f, 0.05f}),      lambert_material("cream", {0.85f, 0.8f, 0.65f}),
                       lambert_material("yellow", {0.9f, 0.75f, 0.1f}),    lambert_material("blue", {0.05f, 0.15f, 0.7f}),
                       lambert_material("green", {0.1f, 0.6f, 0.15f}),     lambert_material("pale", {0.75f, 0.85f, 0.75f})};
    auto add_mesh = [&](const char* name, Primitive a, int ma, Primitive b, int mb) {
        a.material = ma;
        b.material = mb;
        compute_bounds(a);
        compute_bounds(b);
        scene.meshes.push_back({name, {std::move(a), std::move(b)}});
        Node node;
        node.name = name;
        node.mesh = static_cast<int>(scene.meshes.size()) - 1;
        scene.roots.push_back(static_cast<int>(scene.nodes.size()));
        scene.nodes.push_back(node);
    };

    // Back wall (z = -6, 12 from the camera) and floor (y = 0): 1 x 1 checkers, white and dark.
    {
        Primitive a, b;
        for (int i = -8; i < 8; ++i)
            for (int j = -3; j < 7; ++j)
                append_quad((i + j) % 2 == 0 ? a : b, {static_cast<float>(i), static_cast<float>(j), -6.0f}, {1, 0, 0}, {0, 1, 0});
        add_mesh("wall", std::move(a), white, std::move(b), dark);
    }
    {
        Primitive a, b;
        for (int i = -8; i < 8; ++i)
            for (int k = -6; k < 7; ++k)
                append_quad((i + k) % 2 == 0 ? a : b, {static_cast<float>(i), 0.0f, static_cast<float>(k) + 1.0f}, {1, 0, 0}, {0, 0, -1});
        add_mesh("floor", std::move(a), pale, std::move(b), dark);
    }
    // The subject, in focus at z = 0: a column of red and cream bands of 0.2.
    {
        Primitive a, b;
        for (int k = 0; k < 7; ++k)
            append_box(k % 2 == 0 ? a : b, {-0.35f, 0.2f * static_cast<float>(k), -0.35f}, {0.35f, 0.2f * static_cast<float>(k + 1), 0.35f});
        add_mesh("subject", std::move(a), red, std::move(b), cream);
    }
    // The near object, 3 from the camera, left of the subject and overlapping it on screen: a
    // column of yellow and blue 0.25 cubes checkered in x and y.
    {
        Primitive a, b;
        for (int i = 0; i < 2; ++i)
            for (int k = 0; k < 7; ++k) {
                const float x = -0.65f + 0.25f * static_cast<float>(i), y = 0.25f * static_cast<float>(k);
                append_box((i + k) % 2 == 0 ? a : b, {x, y, 2.75f}, {x + 0.25f, y + 0.25f, 3.0f});
            }
        add_mesh("near", std::move(a), yellow, std::move(b), blue);
    }
    // The far object, 9 from the camera, right of the subject: green and white 0.4 cubes.
    {
        Primitive a, b;
        for (int i = 0; i < 2; ++i)
            for (int k = 0; k < 6; ++k) {
                const float x = 1.0f + 0.4f * static_cast<float>(i), y = 0.4f * static_cast<float>(k);
                append_box((i + k) % 2 == 0 ? a : b, {x, y, -3.4f}, {x + 0.4f, y + 0.4f, -3.0f});
            }
        add_mesh("far", std::move(a), green, std::move(b), white);
    }

    // Shining from above, behind the camera and from the left.
    add_sun(scene, {-0.4f, 0.8f, 0.6f}, 3.0f);

    // A thin lens focused on the subject's front (5.66 along the view axis): aperture (radius) 0.1
    // gives, at 240 pixels of image height, blur circles about 10 pixels across on the near
    // object, 4 on the far one and 6 on the back wall.
    const glm::vec3 eye(0.0f, 1.1f, 6.0f), target(0.0f, 0.7f, 0.0f);
    Camera& camera = add_look_at_camera(scene, eye, target, 0.7f, glm::vec3(0, 1, 0), "dof");
    camera.aperture = 0.1f;
    camera.focus_distance = glm::dot(glm::vec3(0.0f, 0.7f, 0.35f) - eye, glm::normalize(target - eye));
    scene.update_world_transforms();
    return scene;
}

}  // namespace candela
