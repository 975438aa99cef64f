#include "scene/features.hpp"

#include <algorithm>
#include <set>

namespace candela {

SceneFeatures analyze_features(const Scene& scene, float reflection_roughness) {
    SceneFeatures f;
    f.shadows.name = "shadows";
    f.transparency.name = "transparency";
    f.reflections.name = "reflections";
    f.transmission.name = "transmission";
    f.emissive_area_lights.name = "emissive area lights";
    f.environment.name = "environment";
    f.material_layers.name = "material layers";

    // Materials actually drawn (reachable nodes with meshes).
    std::set<int> used;
    std::size_t drawn_primitives = 0;
    std::vector<int> stack(scene.roots.begin(), scene.roots.end());
    while (!stack.empty()) {
        const Node& node = scene.nodes[static_cast<size_t>(stack.back())];
        stack.pop_back();
        stack.insert(stack.end(), node.children.begin(), node.children.end());
        if (node.mesh < 0) continue;
        for (const Primitive& p : scene.meshes[static_cast<size_t>(node.mesh)].primitives) {
            used.insert(p.material);
            ++drawn_primitives;
            f.emissive_primitives += scene.material(p.material).is_emissive() && !p.indices.empty();
        }
    }
    int blend = 0, mirrors = 0, transmissive = 0, emissive = 0;
    for (int mi : used) {
        const Material& m = scene.material(mi);
        blend += m.alpha_mode == AlphaMode::blend;
        mirrors += m.metallic > 0.5f && m.roughness < reflection_roughness;
        transmissive += m.transmission > 0.0f;
        emissive += m.is_emissive();
    }
    const auto lights = scene.placed_lights();
    auto set = [](Feature& feat, bool on, std::string why) {
        feat.needed = on;
        feat.reason = std::move(why);
    };
    const bool any_light = !lights.empty() || emissive > 0;
    // One primitive can shadow itself (a duck's head on its body), so any drawn geometry counts.
    set(f.shadows, any_light && drawn_primitives >= 1,
        !any_light ? "no punctual or emissive lights"
        : drawn_primitives < 1 ? "no geometry to cast or receive shadows"
                               : std::to_string(lights.size()) + " punctual light(s) and " + std::to_string(emissive) +
                                     " emissive material(s) over " + std::to_string(drawn_primitives) + " primitives");
    set(f.transparency, blend > 0, blend ? std::to_string(blend) + " BLEND material(s)" : "no BLEND materials");
    set(f.reflections, mirrors + transmissive > 0,
        mirrors + transmissive ? std::to_string(mirrors) + " metallic material(s) with roughness < " +
                                     std::to_string(reflection_roughness).substr(0, 4) + ", " +
                                     std::to_string(transmissive) + " transmissive"
                               : "no smooth metallic or transmissive materials");
    set(f.transmission, transmissive > 0,
        transmissive ? std::to_string(transmissive) + " material(s) with KHR_materials_transmission" : "no transmissive materials");
    set(f.emissive_area_lights, emissive > 0,
        emissive ? std::to_string(emissive) + " emissive material(s) (area lights for the ray tracer)" : "no emissive materials");
    const auto layered = std::count_if(scene.materials.begin(), scene.materials.end(), [](const Material& m) { return m.has_layers(); });
    set(f.material_layers, layered > 0,
        layered ? std::to_string(layered) + " material(s) with extension layers (clearcoat, sheen, anisotropy, iridescence, unlit) "
                                            "or extension textures"
                : "no material extension layers");
    set(f.environment, scene.environment.present(),
        scene.environment.image          ? scene.environment.label
        : !scene.environment.map.empty() ? "map " + scene.environment.map.filename().string()
        : scene.environment.present()  ? "constant radiance"
                                       : "no environment light");
    return f;
}

}  // namespace candela
