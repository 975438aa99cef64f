// generated:materials: the layers of the glTF material extensions side by side, one sphere each
// on a grey floor, lit by a sun and a constant sky: the scene of the material_layers accuracy
// section (raster with and without its layers against the path tracer).
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

#include "scene/generate.hpp"
#include "scene/mesh_utils.hpp"

namespace candela {

Scene make_materials_scene() {
    Scene scene;
    scene.source = "generated:materials";
    const glm::vec3 red(0.6f, 0.08f, 0.05f);
    scene.materials.reserve(8);  // the pointers below stay valid
    auto material = [&](const char* name, glm::vec3 base, float metallic, float roughness) {
        Material m = lambert_material(name, base);
        m.metallic = metallic;
        m.roughness = roughness;
        scene.materials.push_back(m);
        return &scene.materials.back();
    };
    material("floor", glm::vec3(0.5f), 0.0f, 0.9f);
    material("plain", red, 0.0f, 0.5f);
    Material* coat = material("clearcoat", red, 0.0f, 0.6f);
    coat->clearcoat = 1.0f;
    coat->clearcoat_roughness = 0.05f;
    Material* sheen = material("sheen", glm::vec3(0.1f, 0.05f, 0.3f), 0.0f, 0.9f);
    sheen->sheen_color = glm::vec3(1.0f, 0.8f, 0.6f);
    sheen->sheen_roughness = 0.4f;
    Material* aniso = material("anisotropic metal", glm::vec3(0.9f, 0.85f, 0.8f), 1.0f, 0.35f);
    aniso->anisotropy = 0.8f;
    Material* film = material("iridescent", glm::vec3(0.05f), 0.0f, 0.25f);
    film->iridescence = 1.0f;
    film->iridescence_thickness_max = 450.0f;
    Material* both = material("clearcoat over sheen", glm::vec3(0.2f, 0.3f, 0.05f), 0.0f, 0.8f);
    both->sheen_color = glm::vec3(0.6f);
    both->sheen_roughness = 0.5f;
    both->clearcoat = 0.8f;
    both->clearcoat_roughness = 0.2f;

    Primitive floor;
    floor.material = 0;
    append_quad(floor, glm::vec3(-6.0f, 0.0f, 4.0f), glm::vec3(12.0f, 0.0f, 0.0f), glm::vec3(0.0f, 0.0f, -8.0f));
    add_mesh_node(scene, "floor", std::move(floor));
    for (int i = 0; i < 6; ++i) {
        // UVs along longitude and latitude give the tangents (the direction of anisotropy runs
        // around the sphere).
        Primitive s = uv_sphere(0.8f, 24);
        const int segments = 48;
        for (size_t k = 0; k < s.vertices.size(); ++k) {
            const int ring = static_cast<int>(k) / (segments + 1), seg = static_cast<int>(k) % (segments + 1);
            s.vertices[k].uv0 = glm::vec2(static_cast<float>(seg) / segments, static_cast<float>(ring) / 24.0f);
        }
        generate_tangents(s, 0);
        s.material = i + 1;
        const float x = -4.5f + 1.8f * static_cast<float>(i);
        add_mesh_node(scene, scene.materials[static_cast<size_t>(i + 1)].name, std::move(s), glm::translate(glm::mat4(1.0f), glm::vec3(x, 0.8f, 0.0f)));
    }
    add_sun(scene, glm::normalize(glm::vec3(-0.4f, 1.0f, 0.7f)), 2.5f);
    scene.environment.radiance = glm::vec3(0.35f, 0.4f, 0.5f);
    add_look_at_camera(scene, glm::vec3(0.0f, 3.2f, 7.5f), glm::vec3(0.0f, 0.6f, 0.0f), 0.75f);
    scene.update_world_transforms();
    return scene;
}

}  // namespace candela
