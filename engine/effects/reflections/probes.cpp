#include "effects/reflections/probes.hpp"

#include <map>

#include "effects/reflections/reflections.hpp"

namespace candela {

bool is_reflective(const Material& m, float max_roughness) {
    return (m.metallic > 0.5f && m.roughness < max_roughness) || m.transmission > 0.0f;
}

std::vector<ProbePlacement> place_probes(const Scene& scene, const std::vector<GpuScene::Draw>& draws,
                                         const ReflectionsOptions& options) {
    std::vector<ProbePlacement> out;
    if (options.placement == ProbePlacementMode::scene) {
        for (const Node& node : scene.nodes) {
            if (!node.reflection_probe) continue;
            const ReflectionProbe& rp = *node.reflection_probe;
            ProbePlacement p;
            p.origin = "node '" + node.name + "'";
            p.position = glm::vec3(node.world * glm::vec4(rp.position, 1.0f));
            if (rp.has_extent) {
                const glm::vec3 c = glm::vec3(node.world * glm::vec4(rp.center, 1.0f));
                p.has_box = true;
                p.box_min = c - rp.extent;
                p.box_max = c + rp.extent;
            } else {
                // No box: it covers the whole scene (as the nearest probe).
                p.radius = 3.0e38f;
            }
            out.push_back(p);
        }
    }
    if (out.empty()) {
        // One probe per node that draws a reflective material, over the node's bounds.
        std::map<int, Bounds> nodes;
        for (const GpuScene::Draw& d : draws)
            if (d.alpha_mode != AlphaMode::blend &&
                is_reflective(scene.material(d.primitive_material), options.max_roughness))
                nodes[d.node].extend(d.world_bounds);
        for (const auto& [node, bounds] : nodes) {
            ProbePlacement p;
            p.origin = "auto: '" + scene.nodes[static_cast<size_t>(node)].name + "'";
            p.position = bounds.center();
            // Its bounding sphere, slightly enlarged so that every surface point is covered.
            p.radius = 0.5f * glm::length(bounds.extent()) * 1.01f + 1e-4f;
            p.reflective_only = options.max_roughness;
            out.push_back(p);
        }
    }
    for (ProbePlacement& p : out)
        for (size_t i = 0; i < draws.size(); ++i) {
            const Bounds& b = draws[i].world_bounds;
            const glm::vec3 eps(1e-5f * (1.0f + glm::length(b.extent())));
            if (glm::all(glm::greaterThanEqual(p.position, b.min - eps)) && glm::all(glm::lessThanEqual(p.position, b.max + eps)))
                p.excluded_draws.push_back(static_cast<int>(i));
        }
    return out;
}

ProbeData to_gpu(const ProbePlacement& p) {
    ProbeData d{};
    d.position = p.position;
    d.radius = p.radius;
    d.box_min = p.box_min;
    d.has_box = p.has_box ? 1.0f : 0.0f;
    d.box_max = p.box_max;
    d.reflective_only = p.reflective_only;
    return d;
}

}  // namespace candela
