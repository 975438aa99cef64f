// generated:skinned:N — a skinned tube of about N triangles bending back and forth:
// the animation cost benchmark (skinning, GPU upload, BVH rebuild or refit, raster) at any size,
// e.g. generated:skinned:1000000.
#include <algorithm>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

#include "scene/generate.hpp"
#include "scene/mesh_utils.hpp"

namespace candela {

Scene make_skinned_scene(std::size_t triangles) {
    Scene scene;
    scene.source = "generated:skinned:" + std::to_string(triangles);
    Material skin_mat;
    skin_mat.name = "tube";
    skin_mat.base_color = glm::vec4(0.75f, 0.45f, 0.3f, 1.0f);
    skin_mat.metallic = 0.0f;
    skin_mat.roughness = 0.6f;
    Material floor_mat;
    floor_mat.name = "floor";
    floor_mat.base_color = glm::vec4(0.7f, 0.7f, 0.7f, 1.0f);
    floor_mat.metallic = 0.0f;
    floor_mat.roughness = 0.9f;
    scene.materials = {skin_mat, floor_mat};

    // A tube along +y of height 4 and radius 0.2: `around` vertices per ring, `rows` rings,
    // 2 * around * (rows - 1) triangles.
    constexpr float kHeight = 4.0f, kRadius = 0.2f, kPi = 3.14159265358979f;
    constexpr int kBones = 8;
    const int around = triangles >= 200000 ? 128 : 32;
    const int rows = std::max(2, static_cast<int>(triangles / (2 * static_cast<std::size_t>(around))) + 1);
    const float bone = kHeight / kBones;
    Primitive tube;
    tube.material = 0;
    tube.influence_sets = 1;
    tube.vertices.reserve(static_cast<std::size_t>(rows) * static_cast<std::size_t>(around + 1));
    for (int r = 0; r < rows; ++r) {
        const float y = kHeight * static_cast<float>(r) / static_cast<float>(rows - 1);
        // Two influences: the bones whose centres bracket y, blended linearly between the centres.
        const float f = std::clamp(y / bone - 0.5f, 0.0f, static_cast<float>(kBones - 1));
        const int b0 = std::min(static_cast<int>(f), kBones - 2);
        const float w1 = std::clamp(f - static_cast<float>(b0), 0.0f, 1.0f);
        for (int a = 0; a <= around; ++a) {
            const float ph = 2.0f * kPi * static_cast<float>(a) / static_cast<float>(around);
            Vertex v;
            v.normal = glm::vec3(std::cos(ph), 0.0f, std::sin(ph));
            v.position = glm::vec3(0.0f, y, 0.0f) + kRadius * v.normal;
            v.tangent = glm::vec4(0.0f, 1.0f, 0.0f, 1.0f);
            v.uv0 = glm::vec2(static_cast<float>(a) / static_cast<float>(around), y / kHeight);
            tube.vertices.push_back(v);
            tube.joints.push_back(glm::u16vec4(static_cast<std::uint16_t>(b0), static_cast<std::uint16_t>(b0 + 1), 0, 0));
            tube.weights.push_back(glm::vec4(1.0f - w1, w1, 0.0f, 0.0f));
        }
    }
    for (int r = 0; r + 1 < rows; ++r)
        for (int a = 0; a < around; ++a) {
            const auto i = static_cast<std::uint32_t>(r * (around + 1) + a), j = i + static_cast<std::uint32_t>(around + 1);
            tube.indices.insert(tube.indices.end(), {i, j, i + 1, i + 1, j, j + 1});
        }
    tube.rest = tube.vertices;
    compute_bounds(tube);

    Primitive floor;
    floor.material = 1;
    append_quad(floor, {-4, 0, 4}, {8, 0, 0}, {0, 0, -8});
    compute_bounds(floor);
    scene.meshes.push_back({"tube", {std::move(tube)}, {}});
    scene.meshes.push_back({"floor", {std::move(floor)}, {}});

    // Nodes: 0 tube (skinned), 1 floor, 2 sun, 3.. the bone chain (bone k at y = k * bone in its
    // parent's space; the first at the origin).
    Node tube_node, floor_node, sun_node;
    tube_node.name = "tube";
    tube_node.mesh = 0;
    tube_node.skin = 0;
    floor_node.name = "floor";
    floor_node.mesh = 1;
    Light sun;
    sun.name = "sun";
    sun.type = LightType::directional;
    sun.intensity = 3.0f;
    scene.lights.push_back(sun);
    sun_node.name = "sun";
    sun_node.light = 0;
    sun_node.local = glm::mat4(glm::mat3(glm::vec3(1, 0, 0), glm::normalize(glm::vec3(0, 0.6f, -0.8f)), glm::normalize(glm::vec3(0, 0.8f, 0.6f))));
    scene.nodes = {tube_node, floor_node, sun_node};
    scene.roots = {0, 1, 2, 3};
    Skin skin;
    skin.name = "spine";
    Animation anim;
    anim.name = "sway";
    constexpr int kKeys = 9;
    constexpr float kDuration = 2.0f;
    for (int k = 0; k < kBones; ++k) {
        Node b;
        b.name = "bone" + std::to_string(k);
        b.translation = glm::vec3(0.0f, k == 0 ? 0.0f : bone, 0.0f);
        b.local = glm::translate(glm::mat4(1.0f), b.translation);
        const int index = static_cast<int>(scene.nodes.size());
        if (k > 0) {
            b.parent = index - 1;
            scene.nodes[static_cast<std::size_t>(index - 1)].children.push_back(index);
        }
        scene.nodes.push_back(b);
        skin.joints.push_back(index);
        // The bone's bind pose: its rest world is a translation to (0, k * bone, 0); the joint
        // matrix bends vertices about the bone's base.
        skin.inverse_bind.push_back(glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, -static_cast<float>(k) * bone, 0.0f)));
        // Each bone turns about z by a = 0.25 sin(2 pi (t / T) + k / 2): a travelling wave.
        AnimationSampler s;
        s.width = 4;
        s.interpolation = Interpolation::linear;
        for (int i = 0; i < kKeys; ++i) {
            const float t = kDuration * static_cast<float>(i) / static_cast<float>(kKeys - 1);
            const float a = 0.25f * std::sin(2.0f * kPi * t / kDuration + 0.5f * static_cast<float>(k));
            const glm::quat q = glm::angleAxis(a, glm::vec3(0.0f, 0.0f, 1.0f));
            s.times.push_back(t);
            s.values.insert(s.values.end(), {q.x, q.y, q.z, q.w});
        }
        anim.channels.push_back({static_cast<int>(anim.samplers.size()), index, AnimationPath::rotation});
        anim.samplers.push_back(std::move(s));
    }
    anim.start = 0.0f;
    anim.end = kDuration;
    scene.skins.push_back(std::move(skin));
    scene.animations.push_back(std::move(anim));
    scene.environment.radiance = glm::vec3(0.2f);
    add_look_at_camera(scene, {0.0f, 2.2f, 6.5f}, {0.0f, 1.9f, 0.0f}, 0.8f, glm::vec3(0, 1, 0), "front");
    scene.update_world_transforms();
    return scene;
}

}  // namespace candela
