// generated:motion, the motion-blur scene: a glTF-style animation (LINEAR samplers)
// moves two boxes in view over a checkered floor and back wall, lit by one directional light.
// - "slider": a red and cream banded box that translates along x from -12 to +12 over the
//   animation's one second (24 units/s: at 30 fps with camera.shutter=1 it moves 0.8 units, about
//   30 pixels at 320 x 240, during the shutter); it is at x = 0, mid-screen, at t = 0.5.
// - "spinner": a box of two colours, right of centre and floating, turning about the view axis
//   (z) twice per second (nine rotation keys 90 degrees apart, slerped: 24 degrees per shutter).
// Animation 0, "motion", spans [0, 1] s; the accuracy bench poses it at its midpoint, 0.5 s.
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

#include "scene/generate.hpp"
#include "scene/mesh_utils.hpp"

namespace candela {
Scene make_motion_scene() {
    Scene scene;
    scene.source = "generated:motion";
    enum { white, dark, red, cream, yellow, blue, pale };
    scene.materials = {lambert_material("white", glm::vec3(0.8f)),    lambert_material("dark", glm::vec3(0.05f)),
                       lambert_material("red", {0.8f, 0.08f, 0.05f}), lambert_material("cream", {0.85f, 0.8f, 0.65f}),
                       lambert_material("yellow", {0.9f, 0.75f, 0.1f}), lambert_material("blue", {0.05f, 0.15f, 0.7f}),
                       lambert_material("pale", {0.75f, 0.85f, 0.75f})};
    // A node with a two-primitive mesh at `t`; returns its index.
    auto add_mesh = [&](const char* name, Primitive a, int ma, Primitive b, int mb, glm::vec3 t) {
        a.material = ma;
        b.material = mb;
        compute_bounds(a);
        compute_bounds(b);
        scene.meshes.push_back({name, {std::move(a), std::move(b)}, {}});
        Node node;
        node.name = name;
        node.mesh = static_cast<int>(scene.meshes.size()) - 1;
        node.translation = t;
        node.local = glm::translate(glm::mat4(1.0f), t);
        scene.roots.push_back(static_cast<int>(scene.nodes.size()));
        scene.nodes.push_back(node);
        return static_cast<int>(scene.nodes.size()) - 1;
    };

    // Back wall (z = -4) and floor (y = 0): 1 x 1 checkers.
    {
        Primitive a, b;
        for (int i = -10; i < 10; ++i)
            for (int j = 0; j < 8; ++j)
                append_quad((i + j) % 2 == 0 ? a : b, {static_cast<float>(i), static_cast<float>(j), -4.0f}, {1, 0, 0}, {0, 1, 0});
        add_mesh("wall", std::move(a), white, std::move(b), dark, glm::vec3(0.0f));
    }
    {
        Primitive a, b;
        for (int i = -10; i < 10; ++i)
            for (int k = -4; k < 10; ++k)
                append_quad((i + k) % 2 == 0 ? a : b, {static_cast<float>(i), 0.0f, static_cast<float>(k) + 1.0f}, {1, 0, 0}, {0, 0, -1});
        add_mesh("floor", std::move(a), pale, std::move(b), dark, glm::vec3(0.0f));
    }
    // The slider: a 0.8 box of red and cream bands 0.2 wide (vertical: the blur runs across them),
    // resting on the floor, centred on its node.
    int slider = -1;
    {
        Primitive a, b;
        for (int k = 0; k < 4; ++k) {
            const float x = -0.4f + 0.2f * static_cast<float>(k);
            append_box(k % 2 == 0 ? a : b, {x, -0.4f, -0.4f}, {x + 0.2f, 0.4f, 0.4f});
        }
        slider = add_mesh("slider", std::move(a), red, std::move(b), cream, {0.0f, 0.4f, 0.5f});
    }
    // The spinner: a 1.0 x 0.6 x 0.6 box, yellow on the left half and blue on the right, floating
    // right of centre.
    int spinner = -1;
    {
        Primitive a, b;
        append_box(a, {-0.5f, -0.3f, -0.3f}, {0.0f, 0.3f, 0.3f});
        append_box(b, {0.0f, -0.3f, -0.3f}, {0.5f, 0.3f, 0.3f});
        spinner = add_mesh("spinner", std::move(a), yellow, std::move(b), blue, {2.2f, 1.6f, 0.0f});
    }

    Animation anim;
    anim.name = "motion";
    {
        AnimationSampler s;
        s.times = {0.0f, 1.0f};
        s.values = {-12.0f, 0.4f, 0.5f, 12.0f, 0.4f, 0.5f};
        s.width = 3;
        s.interpolation = Interpolation::linear;
        anim.samplers.push_back(s);
        anim.channels.push_back({0, slider, AnimationPath::translation});
    }
    {
        AnimationSampler s;
        s.width = 4;
        s.interpolation = Interpolation::linear;
        for (int k = 0; k <= 8; ++k) {
            const float half = 0.5f * static_cast<float>(k) * 0.5f * 3.14159265f;  // half of k * 90 degrees
            s.times.push_back(static_cast<float>(k) / 8.0f);
            s.values.insert(s.values.end(), {0.0f, 0.0f, std::sin(half), std::cos(half)});  // xyzw about +z
        }
        anim.samplers.push_back(s);
        anim.channels.push_back({1, spinner, AnimationPath::rotation});
    }
    anim.start = 0.0f;
    anim.end = 1.0f;
    scene.animations.push_back(anim);

    // From above, behind the camera and from the left: the shadows fall behind and right of the boxes.
    add_sun(scene, {-0.4f, 0.9f, 0.5f}, 3.0f);

    add_look_at_camera(scene, {0.0f, 2.2f, 8.0f}, {0.6f, 0.9f, 0.0f}, 0.7f, glm::vec3(0, 1, 0), "motion");
    scene.update_world_transforms();
    return scene;
}

}  // namespace candela
