#pragma once
// What a successfully loaded Scene promises to everything after the loader (the renderer, the ray
// tracer, the tests). Shared by the fuzz target (tests/fuzz/fuzz_gltf.cpp), which aborts on the
// first broken promise, and by the unit test that replays the fuzz corpus without clang.
#include <cmath>
#include <cstddef>
#include <string>

#include <glm/glm.hpp>

#include "rt/rt_geometry.hpp"
#include "scene/features.hpp"
#include "scene/scene.hpp"

namespace candela::fuzz {

inline bool finite(const glm::vec2& v) { return std::isfinite(v.x) && std::isfinite(v.y); }
inline bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
inline bool finite(const glm::vec4& v) { return finite(glm::vec3(v)) && std::isfinite(v.w); }
inline bool finite(const glm::mat4& m) { return finite(m[0]) && finite(m[1]) && finite(m[2]) && finite(m[3]); }

// Returns an empty string when every promise holds, else the first broken one.
inline std::string scene_violation(const Scene& scene) {
    const auto in = [](int i, std::size_t n) { return i >= 0 && static_cast<std::size_t>(i) < n; };
    const auto texture_ok = [&](const TextureRef& t) { return t.image == -1 || in(t.image, scene.images.size()); };
    for (std::size_t m = 0; m < scene.materials.size(); ++m) {
        const Material& mat = scene.materials[m];
        const std::string where = "materials[" + std::to_string(m) + "]";
        if (!texture_ok(mat.base_color_texture) || !texture_ok(mat.metallic_roughness_texture) ||
            !texture_ok(mat.normal_texture) || !texture_ok(mat.occlusion_texture) || !texture_ok(mat.emissive_texture))
            return where + ": texture index out of range";
        if (!finite(mat.base_color) || !finite(mat.emissive) || !std::isfinite(mat.metallic) ||
            !std::isfinite(mat.roughness) || !std::isfinite(mat.emissive_strength) || !std::isfinite(mat.ior))
            return where + ": non-finite factor";
    }
    for (std::size_t i = 0; i < scene.images.size(); ++i) {
        const Image& img = scene.images[i];
        if (img.valid && (img.width <= 0 || img.height <= 0 ||
                          img.rgba8.size() != static_cast<std::size_t>(img.width) * static_cast<std::size_t>(img.height) * 4))
            return "images[" + std::to_string(i) + "]: pixel count does not match its size";
    }
    for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
        for (std::size_t p = 0; p < scene.meshes[m].primitives.size(); ++p) {
            const Primitive& prim = scene.meshes[m].primitives[p];
            const std::string where = "meshes[" + std::to_string(m) + "].primitives[" + std::to_string(p) + "]";
            if (prim.indices.size() % 3 != 0) return where + ": index count is not a multiple of 3";
            for (std::uint32_t index : prim.indices)
                if (index >= prim.vertices.size()) return where + ": index out of range";
            if (prim.material != -1 && !in(prim.material, scene.materials.size())) return where + ": material out of range";
            for (const Vertex& v : prim.vertices) {
                if (!finite(v.position) || !finite(v.normal) || !finite(v.tangent) || !finite(v.uv0) || !finite(v.uv1) ||
                    !finite(v.color))
                    return where + ": non-finite vertex attribute";
                if (std::abs(glm::length(v.normal) - 1.0f) > 1e-3f) return where + ": normal is not unit length";
            }
        }
    }
    for (std::size_t n = 0; n < scene.nodes.size(); ++n) {
        const Node& node = scene.nodes[n];
        const std::string where = "nodes[" + std::to_string(n) + "]";
        if (node.mesh != -1 && !in(node.mesh, scene.meshes.size())) return where + ": mesh out of range";
        if (node.camera != -1 && !in(node.camera, scene.cameras.size())) return where + ": camera out of range";
        if (node.light != -1 && !in(node.light, scene.lights.size())) return where + ": light out of range";
        if (node.parent != -1 && !in(node.parent, scene.nodes.size())) return where + ": parent out of range";
        for (int c : node.children)
            if (!in(c, scene.nodes.size()) || scene.nodes[static_cast<std::size_t>(c)].parent != static_cast<int>(n))
                return where + ": child out of range or with another parent";
        if (!finite(node.world)) return where + ": non-finite world transform";
        if (node.sphere_radius && !(*node.sphere_radius > 0.0f && std::isfinite(*node.sphere_radius)))
            return where + ": sphere radius not positive and finite";
    }
    for (int r : scene.roots)
        if (!in(r, scene.nodes.size()) || scene.nodes[static_cast<std::size_t>(r)].parent != -1) return "roots: not a root node";
    for (std::size_t c = 0; c < scene.cameras.size(); ++c) {
        const Camera& cam = scene.cameras[c];
        if (!(cam.znear > 0.0f) || !std::isfinite(cam.znear) || !(cam.zfar == 0.0f || cam.zfar > cam.znear) ||
            (!cam.orthographic && !(cam.yfov > 0.0f && cam.yfov < 3.1416f)))
            return "cameras[" + std::to_string(c) + "]: unusable projection";
    }
    for (std::size_t l = 0; l < scene.lights.size(); ++l) {
        const Light& light = scene.lights[l];
        if (!finite(light.color) || !std::isfinite(light.intensity) || !std::isfinite(light.range) ||
            !std::isfinite(light.inner_cone) || !std::isfinite(light.outer_cone))
            return "lights[" + std::to_string(l) + "]: non-finite parameter";
    }
    for (const WorldTriangle& t : scene.world_triangles())
        for (int k = 0; k < 3; ++k)
            if (!finite(t.p[k]) || !finite(t.n[k])) return "world triangles: non-finite position or normal";
    return {};
}

// Everything after the loader that must hold for a loaded scene: its promises, then the scene
// features and the ray tracer's geometry and BVH (which must hold every primitive), and the BVH's
// GPU traversal layout.
inline std::string built_scene_violation(const Scene& scene) {
    std::string broken = scene_violation(scene);
    if (!broken.empty()) return broken;
    (void)analyze_features(scene);
    const rt::RtGeometry g = rt::build_rt_geometry(scene, static_cast<int>(scene.materials.size()));
    const std::size_t prims = g.triangles.size() + g.spheres.size();
    if (g.bvh.prim_indices.size() != prims)
        return "the BVH holds " + std::to_string(g.bvh.prim_indices.size()) + " primitives, the scene " + std::to_string(prims);
    const std::string layout = rt::traversal_layout_violation(g, rt::pack_traversal(g));
    if (!layout.empty()) return "the BVH's traversal layout: " + layout;
    return {};
}

}  // namespace candela::fuzz
