// The area_lights effect's splitting of emissive draws into light pieces (area_light_pieces,
// declared with AreaPiece in render/gpu_scene.hpp): GpuScene::update_lights appends the pieces to
// the light buffer after the punctual lights, and the effect reads the same pieces for its own
// per-piece data. Defined here, beside the effect that the pieces serve.
#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "effects/area_lights/area_lights.hpp"
#include "render/gpu_scene.hpp"
#include "scene/scene.hpp"

namespace candela {

namespace {

struct MicroPatch {
    glm::vec3 centroid;
    glm::vec3 normal_area;  // normal * area
    float area;
};

// Splits patches[lo, hi) into `pieces` groups of about equal area: sort along the longest axis of
// their centroids and cut at the area quantile, recursively.
void split_patches(std::vector<MicroPatch>& patches, size_t lo, size_t hi, int pieces, std::vector<std::pair<size_t, size_t>>& out) {
    if (pieces <= 1 || hi - lo <= 1) {
        out.emplace_back(lo, hi);
        return;
    }
    Bounds b;
    for (size_t i = lo; i < hi; ++i) b.extend(patches[i].centroid);
    const glm::vec3 e = b.extent();
    const int axis = e.x >= e.y && e.x >= e.z ? 0 : e.y >= e.z ? 1 : 2;
    std::sort(patches.begin() + static_cast<std::ptrdiff_t>(lo), patches.begin() + static_cast<std::ptrdiff_t>(hi),
              [axis](const MicroPatch& a, const MicroPatch& c) { return a.centroid[axis] < c.centroid[axis]; });
    const int left = pieces / 2;
    float total = 0.0f;
    for (size_t i = lo; i < hi; ++i) total += patches[i].area;
    const float target = total * static_cast<float>(left) / static_cast<float>(pieces);
    float acc = 0.0f;
    size_t mid = lo;
    while (mid < hi - 1 && acc + patches[mid].area * 0.5f < target) acc += patches[mid++].area;
    mid = std::clamp(mid, lo + 1, hi - 1);
    split_patches(patches, lo, mid, left, out);
    split_patches(patches, mid, hi, pieces - left, out);
}

}  // namespace

std::vector<AreaPiece> area_light_pieces(const Scene& scene, const GpuScene& gpu, int samples) {
    std::vector<AreaPiece> out;
    const auto& draws = gpu.draws();
    for (size_t di = 0; di < draws.size(); ++di) {
        const GpuScene::Draw& d = draws[di];
        const Node& node = scene.nodes[static_cast<size_t>(d.node)];
        const Primitive* prim = &scene.meshes[static_cast<size_t>(node.mesh)].primitives[static_cast<size_t>(d.primitive)];
        const Material& m = scene.material(prim->material);
        if (!m.is_emissive()) continue;
        const size_t tris = prim->triangle_count();
        // Enough sub-triangles that every piece gets several.
        int k = 1;
        while (k < 8 && tris * static_cast<size_t>(k * k) < static_cast<size_t>(8 * samples)) ++k;
        std::vector<MicroPatch> patches;
        for (size_t t = 0; t < tris; ++t) {
            glm::vec3 p[3];
            for (int c = 0; c < 3; ++c)
                p[c] = glm::vec3(d.model * glm::vec4(prim->vertices[prim->indices[t * 3 + static_cast<size_t>(c)]].position, 1.0f));
            if (d.mirrored) std::swap(p[1], p[2]);  // a mirroring transform reverses the winding
            const glm::vec3 cr = glm::cross(p[1] - p[0], p[2] - p[0]);
            const float area2 = glm::length(cr);
            if (!(area2 > 0.0f) || !std::isfinite(area2)) continue;
            const float sub_area = 0.5f * area2 / static_cast<float>(k * k);
            // Barycentric grid: k^2 congruent sub-triangles (upright and inverted), their centroids.
            for (int i = 0; i < k; ++i)
                for (int j = 0; j < k - i; ++j)
                    for (int inverted = 0; inverted < (j < k - i - 1 ? 2 : 1); ++inverted) {
                        const float a = (static_cast<float>(i) + (inverted ? 2.0f : 1.0f) / 3.0f) / static_cast<float>(k);
                        const float b = (static_cast<float>(j) + (inverted ? 2.0f : 1.0f) / 3.0f) / static_cast<float>(k);
                        patches.push_back({p[0] + a * (p[1] - p[0]) + b * (p[2] - p[0]), cr / area2 * sub_area, sub_area});
                    }
        }
        if (patches.empty()) continue;
        std::vector<std::pair<size_t, size_t>> groups;
        split_patches(patches, 0, patches.size(), samples, groups);
        for (const auto& [lo, hi] : groups) {
            AreaPiece piece;
            glm::vec3 na(0.0f);
            for (size_t i = lo; i < hi; ++i) {
                piece.centroid += patches[i].centroid * patches[i].area;
                piece.area += patches[i].area;
                na += patches[i].normal_area;
            }
            if (!(piece.area > 0.0f)) continue;
            piece.centroid /= piece.area;
            const float nl = glm::length(na);
            piece.normal = nl > 0.0f ? na / nl : glm::vec3(0.0f, -1.0f, 0.0f);
            piece.power_per_sr = m.emission() * piece.area;
            piece.double_sided = m.double_sided;
            piece.draw = static_cast<int>(di);
            out.push_back(piece);
        }
    }
    return out;
}

}  // namespace candela
