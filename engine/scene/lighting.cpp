#include "scene/lighting.hpp"

#include <algorithm>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

namespace candela {

std::optional<LightingMode> parse_lighting_mode(const std::string& text) {
    if (text == "auto") return LightingMode::auto_select;
    if (text == "file") return LightingMode::file;
    if (text == "default") return LightingMode::default_rig;
    return std::nullopt;
}

const char* to_string(LightingMode mode) {
    switch (mode) {
    case LightingMode::auto_select: return "auto";
    case LightingMode::file: return "file";
    case LightingMode::default_rig: return "default";
    }
    return "?";
}

std::string own_lighting_summary(const Scene& scene) {
    std::string out;
    auto add = [&](const std::string& what) { out += (out.empty() ? "" : ", ") + what; };
    const size_t punctual = scene.placed_lights().size();
    if (punctual) add(std::to_string(punctual) + " punctual light(s)");
    // Emissive materials count only where a drawn primitive uses them, and only as HDR emitters:
    // emission above 1 (glTF's way to author a light-emitting surface is
    // KHR_materials_emissive_strength). Emission up to display white - labels, screens, glowing
    // decals - shows itself but lights nothing much, so such a file still gets the rig.
    int emissive = 0;
    for (const Node& node : scene.nodes) {
        if (node.mesh < 0) continue;
        for (const Primitive& p : scene.meshes[static_cast<size_t>(node.mesh)].primitives) {
            if (p.indices.empty() || !scene.material(p.material).is_emissive()) continue;
            const glm::vec3 e = scene.material(p.material).emission();
            emissive += std::max(e.r, std::max(e.g, e.b)) > 1.0f;
        }
    }
    if (emissive) add(std::to_string(emissive) + " emissive primitive(s) brighter than 1");
    if (scene.environment.present()) add("an environment");
    return out;
}

std::shared_ptr<const ImageF> default_sky_image(int width) {
    const int height = width / 2;
    auto image = std::make_shared<ImageF>(width, height, 4);
    // Radiance by elevation: zenith slightly cool, horizon white, ground a warm grey. The ground
    // fades in over a few degrees below the horizon: a hard edge would alias in the filtered
    // cube and give the tracer's importance sampling a discontinuity for nothing.
    const glm::vec3 zenith(0.70f, 0.78f, 0.90f), horizon(1.0f, 1.0f, 1.0f), ground(0.30f, 0.28f, 0.26f);
    for (int y = 0; y < height; ++y) {
        const float theta = (static_cast<float>(y) + 0.5f) / static_cast<float>(height) * 3.14159265f;
        const float up = std::cos(theta);  // sine of the elevation
        glm::vec3 c;
        if (up >= 0.0f) c = glm::mix(horizon, zenith, std::sqrt(up));
        else c = glm::mix(horizon, ground, glm::smoothstep(0.0f, 0.12f, -up));
        c *= kSkyIntensity;
        for (int x = 0; x < width; ++x) {
            float* p = image->at(x, y);
            p[0] = c.r, p[1] = c.g, p[2] = c.b, p[3] = 1.0f;
        }
    }
    return image;
}

void add_default_environment(Scene& scene) {
    scene.environment = Environment{};
    scene.environment.image = default_sky_image();
    scene.environment.label = "default sky (built in)";
}

LightingChoice apply_lighting(Scene& scene, LightingMode mode, const Camera& view) {
    LightingChoice choice;
    const std::string own = own_lighting_summary(scene);
    switch (mode) {
    case LightingMode::file:
        choice.reason = own.empty() ? "the file's own (--lighting file): none, the image is black" : "the file's own (--lighting file): " + own;
        return choice;
    case LightingMode::auto_select:
        if (!own.empty()) {
            choice.reason = "the file's own: " + own;
            choice.check_view = !scene.environment.present();
            return choice;
        }
        choice.reason = "default rig (the file has no light, no emitter brighter than 1 and no environment; --lighting auto)";
        break;
    case LightingMode::default_rig:
        choice.reason = "default rig (--lighting default" + (own.empty() ? std::string(")") : "; the file's punctual lights and environment are not used)");
        for (Node& node : scene.nodes) node.light = -1;
        break;
    }
    choice.rig = true;
    add_default_environment(scene);

    // The key light, in the camera's frame: from above (0.85), left (-0.5) and the viewer's side
    // (0.7), i.e. about 40 degrees above the view and 30 degrees left of it.
    const glm::mat3 frame(view.world);
    const glm::vec3 right = glm::normalize(frame[0]), up = glm::normalize(frame[1]), back = glm::normalize(frame[2]);
    glm::vec3 to_light = glm::normalize(0.85f * up - 0.5f * right + 0.7f * back);
    // A degenerate camera frame (a zero scale on the camera's node) must not make the light NaN:
    // then the same direction in world axes, as seen by a camera looking down -Z.
    if (glm::any(glm::isnan(to_light)) || glm::any(glm::isinf(to_light))) to_light = glm::normalize(glm::vec3(-0.5f, 0.85f, 0.7f));
    Light key;
    key.name = "default key light";
    key.type = LightType::directional;
    key.color = glm::vec3(1.0f, 0.97f, 0.92f);
    key.intensity = kKeyIrradiance;
    scene.lights.push_back(key);
    Node node;
    node.name = "default key light";
    node.light = static_cast<int>(scene.lights.size()) - 1;
    // The light shines along the node's -Z: look from the light towards the scene.
    const glm::vec3 helper_up = std::fabs(to_light.y) > 0.99f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0);
    node.local = glm::inverse(glm::lookAt(glm::vec3(0.0f), -to_light, helper_up));
    scene.nodes.push_back(node);
    scene.roots.push_back(static_cast<int>(scene.nodes.size()) - 1);
    scene.update_world_transforms();
    return choice;
}

}  // namespace candela
