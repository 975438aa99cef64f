#include "rt/rt_geometry.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace candela::rt {
namespace {

int as_int_bits(float f) {
    int i;
    std::memcpy(&i, &f, 4);
    return i;
}
float from_int_bits(int i) {
    float f;
    std::memcpy(&f, &i, 4);
    return f;
}
float luminance(const glm::vec3& c) { return 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b; }

}  // namespace

RtGeometry build_rt_geometry(const Scene& scene, int default_material, const BvhOptions& options) {
    RtGeometry g;
    for (const WorldTriangle& t : scene.world_triangles()) {
        if (scene.nodes[static_cast<size_t>(t.node)].sphere_radius) continue;  // traced as the exact sphere
        const int material = t.material >= 0 ? t.material : default_material;
        TriangleGpu tri{};
        tri.p0 = glm::vec4(t.p[0], from_int_bits(material));
        tri.p1 = glm::vec4(t.p[1], from_int_bits(t.node));
        tri.p2 = glm::vec4(t.p[2], 0.0f);
        tri.n0 = glm::vec4(t.n[0], 0.0f);
        tri.n1 = glm::vec4(t.n[1], 0.0f);
        tri.n2 = glm::vec4(t.n[2], 0.0f);
        tri.uv_a = glm::vec4(t.uv0[0], t.uv0[1]);
        tri.uv_b = glm::vec4(t.uv0[2], t.uv1[0]);
        tri.uv_c = glm::vec4(t.uv1[1], t.uv1[2]);
        tri.t0 = t.tangent[0];
        tri.t1 = t.tangent[1];
        tri.t2 = t.tangent[2];
        g.triangles.push_back(tri);
    }
    for (size_t i = 0; i < scene.nodes.size(); ++i) {
        const Node& node = scene.nodes[i];
        if (!node.sphere_radius || node.mesh < 0) continue;
        // The radius is in world units for an unscaled node; a scaled node scales it by its
        // largest axis scale (non-uniform scale is not a sphere any more).
        const float scale = std::max({glm::length(glm::vec3(node.world[0])), glm::length(glm::vec3(node.world[1])),
                                      glm::length(glm::vec3(node.world[2]))});
        int material = default_material;
        const Mesh& mesh = scene.meshes[static_cast<size_t>(node.mesh)];
        if (!mesh.primitives.empty() && mesh.primitives[0].material >= 0) material = mesh.primitives[0].material;
        g.spheres.push_back({glm::vec4(glm::vec3(node.world[3]), *node.sphere_radius * scale),
                             glm::ivec4(material, static_cast<int>(i), 0, 0)});
    }
    // Emitters by power.
    std::vector<float> power;
    for (size_t i = 0; i < g.triangles.size(); ++i) {
        const TriangleGpu& t = g.triangles[i];
        const int mat = as_int_bits(t.p0.w);
        const Material& m = scene.material(mat < static_cast<int>(scene.materials.size()) ? mat : -1);
        const glm::vec3 e = m.emission();
        const float area = 0.5f * glm::length(glm::cross(glm::vec3(t.p1 - t.p0), glm::vec3(t.p2 - t.p0)));
        if (luminance(e) <= 0.0f || !(area > 0.0f) || !std::isfinite(area)) continue;
        g.emitters.push_back({static_cast<std::uint32_t>(i), 0.0f, 0.0f, area});
        power.push_back(luminance(e) * area * (m.double_sided ? 2.0f : 1.0f));
    }
    // Emissive spheres (untextured emission) too, sampled by the cone they subtend: their
    // `triangle` is triangles.size() + sphere index, their pdf is also kept in material_node.z.
    for (size_t i = 0; i < g.spheres.size(); ++i) {
        const SphereGpu& sp = g.spheres[i];
        const int mat = sp.material_node.x;
        const Material& m = scene.material(mat < static_cast<int>(scene.materials.size()) ? mat : -1);
        const float r = sp.center_radius.w;
        const float area = 4.0f * 3.14159265f * r * r;
        if (luminance(m.emission()) <= 0.0f || m.emissive_texture.present() || !(area > 0.0f) || !std::isfinite(area)) continue;
        g.emitters.push_back({static_cast<std::uint32_t>(g.triangles.size() + i), 0.0f, 0.0f, area});
        power.push_back(luminance(m.emission()) * area);
    }
    double total = 0.0;
    for (float p : power) total += p;
    g.emitted_power = total;
    double running = 0.0;
    for (size_t i = 0; i < g.emitters.size(); ++i) {
        running += power[i];
        g.emitters[i].pdf = static_cast<float>(power[i] / total);
        g.emitters[i].cdf = static_cast<float>(running / total);
        const std::uint32_t t = g.emitters[i].triangle;
        if (t < g.triangles.size()) g.triangles[t].n0.w = g.emitters[i].pdf;
        else g.spheres[t - g.triangles.size()].material_node.z = as_int_bits(g.emitters[i].pdf);
    }
    if (!g.emitters.empty()) g.emitters.back().cdf = 1.0f;
    double total_area = 0.0;
    for (size_t i = 0; i < g.triangles.size(); ++i) {
        const TriangleGpu& t = g.triangles[i];
        const float area = 0.5f * glm::length(glm::cross(glm::vec3(t.p1 - t.p0), glm::vec3(t.p2 - t.p0)));
        if (!(area > 0.0f) || !std::isfinite(area)) continue;
        g.surfaces.push_back({static_cast<std::uint32_t>(i), 0.0f, 0.0f, area});
        total_area += area;
    }
    double running_area = 0.0;
    for (EmitterGpu& s : g.surfaces) {
        running_area += s.area;
        s.pdf = static_cast<float>(s.area / total_area);
        s.cdf = static_cast<float>(running_area / total_area);
    }
    if (!g.surfaces.empty()) g.surfaces.back().cdf = 1.0f;
    for (const Material& m : scene.materials) {
        g.has_transmission = g.has_transmission || m.transmission > 0.0f;
        g.has_blend = g.has_blend || m.alpha_mode == AlphaMode::blend;
    }

    std::vector<Aabb> boxes;
    boxes.reserve(g.triangles.size() + g.spheres.size());
    for (const TriangleGpu& t : g.triangles) {
        Aabb b;
        b.extend(glm::vec3(t.p0));
        b.extend(glm::vec3(t.p1));
        b.extend(glm::vec3(t.p2));
        boxes.push_back(b);
    }
    for (const SphereGpu& s : g.spheres) {
        Aabb b;
        b.extend(glm::vec3(s.center_radius) - glm::vec3(s.center_radius.w));
        b.extend(glm::vec3(s.center_radius) + glm::vec3(s.center_radius.w));
        boxes.push_back(b);
    }
    g.bvh = build_bvh_binned_sah(boxes, options);
    return g;
}

}  // namespace candela::rt
