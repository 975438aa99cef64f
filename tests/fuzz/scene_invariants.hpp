#pragma once
// What a successfully loaded Scene promises to everything after the loader (the renderer, the ray
// tracer, the tests). Shared by the fuzz target (tests/fuzz/fuzz_gltf.cpp), which aborts on the
// first broken promise, and by the unit test that replays the fuzz corpus without clang.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "rt/rt_geometry.hpp"
#include "scene/features.hpp"
#include "scene/scene.hpp"

namespace candela::fuzz {

inline bool finite(const glm::vec2& v) { return std::isfinite(v.x) && std::isfinite(v.y); }
inline bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
inline bool finite(const glm::vec4& v) { return finite(glm::vec3(v)) && std::isfinite(v.w); }
inline bool finite(const glm::mat4& m) { return finite(m[0]) && finite(m[1]) && finite(m[2]) && finite(m[3]); }

// Skins, morph targets and animations: what posing and sampling rely on.
inline std::string deformation_violation(const Scene& scene) {
    const auto in = [](int i, std::size_t n) { return i >= 0 && static_cast<std::size_t>(i) < n; };
    for (std::size_t k = 0; k < scene.skins.size(); ++k) {
        const Skin& skin = scene.skins[k];
        const std::string where = "skins[" + std::to_string(k) + "]";
        if (skin.joints.empty() || skin.inverse_bind.size() != skin.joints.size()) return where + ": joint and inverse bind counts";
        for (std::size_t j = 0; j < skin.joints.size(); ++j)
            if (!in(skin.joints[j], scene.nodes.size()) || !finite(skin.inverse_bind[j])) return where + ": joint not a node or non-finite matrix";
    }
    std::vector<int> users(scene.meshes.size(), 0);
    for (std::size_t n = 0; n < scene.nodes.size(); ++n) {
        const Node& node = scene.nodes[n];
        const std::string where = "nodes[" + std::to_string(n) + "]";
        if (node.skin != -1 && !in(node.skin, scene.skins.size())) return where + ": skin out of range";
        if (!finite(node.translation) || !finite(glm::vec4(node.rotation.x, node.rotation.y, node.rotation.z, node.rotation.w)) ||
            !finite(node.scale))
            return where + ": non-finite TRS";
        if (node.mesh < 0 || !in(node.mesh, scene.meshes.size())) continue;
        ++users[static_cast<std::size_t>(node.mesh)];
        const Mesh& mesh = scene.meshes[static_cast<std::size_t>(node.mesh)];
        if (node.rest_weights.size() != mesh.weights.size()) return where + ": rest weights do not match the mesh's morph targets";
        if (node.skin < 0) continue;
        const std::size_t joints = scene.skins[static_cast<std::size_t>(node.skin)].joints.size();
        for (const Primitive& p : mesh.primitives)
            for (const glm::u16vec4& j : p.joints)
                if (j.x >= joints || j.y >= joints || j.z >= joints || j.w >= joints) return where + ": a vertex joint is out of its skin's range";
    }
    for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
        const Mesh& mesh = scene.meshes[m];
        for (std::size_t p = 0; p < mesh.primitives.size(); ++p) {
            const Primitive& prim = mesh.primitives[p];
            const std::string where = "meshes[" + std::to_string(m) + "].primitives[" + std::to_string(p) + "]";
            if (prim.targets.size() != mesh.weights.size()) return where + ": morph targets do not match the mesh's weights";
            if (!prim.deformable()) {
                if (prim.skinned() || !prim.targets.empty()) return where + ": skinned or morphed but without a rest pose";
                continue;
            }
            if (prim.rest.size() != prim.vertices.size()) return where + ": rest and posed vertex counts differ";
            if (users[m] > 1 && prim.skinned()) return where + ": a skinned primitive drawn by several nodes";
            const std::size_t sets = static_cast<std::size_t>(std::max(prim.influence_sets, 0));
            if (prim.joints.size() != prim.rest.size() * sets || prim.weights.size() != prim.joints.size())
                return where + ": joints/weights do not match the vertices";
            for (const glm::vec4& w : prim.weights)
                if (!finite(w) || glm::any(glm::lessThan(w, glm::vec4(0.0f)))) return where + ": a weight is negative or not finite";
            for (const MorphTarget& t : prim.targets)
                for (const auto* d : {&t.position, &t.normal, &t.tangent}) {
                    if (!d->empty() && d->size() != prim.rest.size()) return where + ": a morph target does not match the vertices";
                    for (const glm::vec3& v : *d)
                        if (!finite(v)) return where + ": a non-finite morph delta";
                }
        }
    }
    for (std::size_t a = 0; a < scene.animations.size(); ++a) {
        const Animation& anim = scene.animations[a];
        const std::string where = "animations[" + std::to_string(a) + "]";
        if (!(anim.start <= anim.end) || !std::isfinite(anim.start) || !std::isfinite(anim.end)) return where + ": start/end";
        for (const AnimationChannel& c : anim.channels) {
            if (!in(c.node, scene.nodes.size()) || !in(c.sampler, anim.samplers.size())) return where + ": channel node or sampler out of range";
            const AnimationSampler& s = anim.samplers[static_cast<std::size_t>(c.sampler)];
            const Node& node = scene.nodes[static_cast<std::size_t>(c.node)];
            const std::size_t width = c.path == AnimationPath::rotation ? 4
                                      : c.path == AnimationPath::weights
                                          ? (node.mesh >= 0 ? scene.meshes[static_cast<std::size_t>(node.mesh)].weights.size() : 0)
                                          : 3;
            if (static_cast<std::size_t>(s.width) != width || width == 0) return where + ": a sampler's width does not fit its channel";
            if (node.has_matrix && c.path != AnimationPath::weights) return where + ": a channel on a matrix node";
            if (s.times.empty() || s.values.size() != s.times.size() * width * (s.interpolation == Interpolation::cubic_spline ? 3 : 1))
                return where + ": a sampler's value count does not fit its times";
            for (std::size_t k = 0; k < s.times.size(); ++k)
                if (!std::isfinite(s.times[k]) || (k > 0 && !(s.times[k] > s.times[k - 1]))) return where + ": times not finite and increasing";
            for (float v : s.values)
                if (!std::isfinite(v)) return where + ": a non-finite keyframe value";
        }
    }
    return {};
}

// Returns an empty string when every promise holds, else the first broken one.
inline std::string scene_violation(const Scene& scene) {
    if (std::string d = deformation_violation(scene); !d.empty()) return d;
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
