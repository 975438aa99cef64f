#pragma once
// Scene pieces the ray tracer's GL tests share: the shader library, a Lambert material without a
// specular lobe, a UV sphere the tracer intersects exactly, an orthographic camera.
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "gltf_builder.hpp"
#include "shader/shader_library.hpp"

namespace candela::test {

inline ShaderLibrary shader_lib() { return ShaderLibrary(std::filesystem::path(CANDELA_SOURCE_DIR) / "shaders"); }

inline nlohmann::json lambert(glm::vec3 color) {
    return {{"pbrMetallicRoughness", {{"baseColorFactor", {color.r, color.g, color.b, 1}}, {"metallicFactor", 0}, {"roughnessFactor", 1}}},
            {"extensions", {{"KHR_materials_specular", {{"specularFactor", 0}}}}}};
}

// A UV sphere of radius r as a mesh; the node gets extras.sphere so the tracer uses the exact one.
inline int add_sphere(GltfBuilder& b, float r, int material) {
    std::vector<glm::vec3> p, n;
    std::vector<uint32_t> idx;
    const int seg = 16, rings = 8;
    for (int i = 0; i <= rings; ++i)
        for (int j = 0; j <= seg; ++j) {
            const float th = 3.14159265f * static_cast<float>(i) / rings, ph = 6.2831853f * static_cast<float>(j) / seg;
            const glm::vec3 d(std::sin(th) * std::cos(ph), std::cos(th), std::sin(th) * std::sin(ph));
            p.push_back(d * r);
            n.push_back(d);
        }
    for (int i = 0; i < rings; ++i)
        for (int j = 0; j < seg; ++j) {
            const uint32_t a = static_cast<uint32_t>(i * (seg + 1) + j), c = a + static_cast<uint32_t>(seg + 1);
            idx.insert(idx.end(), {a, a + 1, c, a + 1, c + 1, c});
        }
    return b.add_mesh({{"POSITION", b.add_positions(p)}, {"NORMAL", b.add_vec3(n)}}, b.add_indices(idx), material);
}

inline void ortho_camera(GltfBuilder& b, glm::vec3 pos, glm::vec4 rotation_xyzw, float half) {
    b.json()["cameras"].push_back({{"type", "orthographic"}, {"orthographic", {{"xmag", half}, {"ymag", half}, {"znear", 0.01}, {"zfar", 100}}}});
    b.add_node({{"camera", b.json()["cameras"].size() - 1}, {"translation", {pos.x, pos.y, pos.z}},
                {"rotation", {rotation_xyzw.x, rotation_xyzw.y, rotation_xyzw.z, rotation_xyzw.w}}});
}

inline const glm::vec4 kLookDown(-0.70710678f, 0.0f, 0.0f, 0.70710678f);  // camera -Z turned to -Y

}  // namespace candela::test
