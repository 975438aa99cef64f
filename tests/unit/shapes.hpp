#pragma once
// Closed meshes for tests, built into a GltfBuilder: shared vertices (no duplicate positions at
// seams or poles), so the meshes are watertight.
#include <cmath>
#include <vector>

#include "gltf_builder.hpp"

namespace candela::test {

// A UV sphere of radius 1 about the origin: `rings` bands, `segments` around, outward normals.
inline int add_closed_sphere(GltfBuilder& b, int material, int rings = 32, int segments = 64) {
    std::vector<glm::vec3> p;
    std::vector<uint32_t> idx;
    p.emplace_back(0.0f, 1.0f, 0.0f);  // north pole: index 0
    for (int r = 1; r < rings; ++r)
        for (int s = 0; s < segments; ++s) {
            const double t = 3.14159265358979 * r / rings, ph = 2.0 * 3.14159265358979 * s / segments;
            p.emplace_back(std::sin(t) * std::cos(ph), std::cos(t), -std::sin(t) * std::sin(ph));
        }
    p.emplace_back(0.0f, -1.0f, 0.0f);  // south pole: last
    const auto ring = [&](int r, int s) { return static_cast<uint32_t>(1 + (r - 1) * segments + (s % segments)); };
    const uint32_t south = static_cast<uint32_t>(p.size() - 1);
    for (int s = 0; s < segments; ++s) idx.insert(idx.end(), {0u, ring(1, s), ring(1, s + 1)});
    for (int r = 1; r < rings - 1; ++r)
        for (int s = 0; s < segments; ++s)
            idx.insert(idx.end(), {ring(r, s), ring(r + 1, s), ring(r, s + 1), ring(r, s + 1), ring(r + 1, s), ring(r + 1, s + 1)});
    for (int s = 0; s < segments; ++s) idx.insert(idx.end(), {ring(rings - 1, s), south, ring(rings - 1, s + 1)});
    return b.add_mesh({{"POSITION", b.add_positions(p)}, {"NORMAL", b.add_vec3(p)}}, b.add_indices(idx), material);
}

// An axis-aligned cube of half size 0.5 about the origin, flat normals (24 vertices).
inline int add_box(GltfBuilder& b, int material) {
    std::vector<glm::vec3> p, n;
    std::vector<uint32_t> idx;
    const glm::vec3 axes[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (int a = 0; a < 3; ++a)
        for (float sign : {1.0f, -1.0f}) {
            const glm::vec3 nn = axes[a] * sign, u = axes[(a + 1) % 3], v = glm::cross(nn, u);
            const uint32_t base = static_cast<uint32_t>(p.size());
            for (const glm::vec2 c : {glm::vec2(-1, -1), glm::vec2(1, -1), glm::vec2(1, 1), glm::vec2(-1, 1)}) {
                p.push_back(0.5f * (nn + u * c.x + v * c.y));
                n.push_back(nn);
            }
            idx.insert(idx.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
        }
    return b.add_mesh({{"POSITION", b.add_positions(p)}, {"NORMAL", b.add_vec3(n)}}, b.add_indices(idx), material);
}

}  // namespace candela::test
