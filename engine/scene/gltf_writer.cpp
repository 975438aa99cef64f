#include "scene/gltf_writer.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <vector>

#include <glm/gtc/type_ptr.hpp>
#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "scene/gltf_validate_internal.hpp"

namespace candela {
namespace {

using nlohmann::json;

// Floats go through double, which nlohmann prints with enough digits to read back exactly.
json vec(const float* v, int n) {
    json a = json::array();
    for (int i = 0; i < n; ++i) a.push_back(static_cast<double>(v[i]));
    return a;
}
json vec3(glm::vec3 v) { return vec(glm::value_ptr(v), 3); }

class Writer {
public:
    explicit Writer(const Scene& scene) : scene_(scene) {}

    json build() {
        refuse_what_is_not_written();
        j_ = {{"asset", {{"version", "2.0"}, {"generator", "Candela gltf_writer"}}}, {"scene", 0}};
        for (const Material& m : scene_.materials) j_["materials"].push_back(material(m));
        for (const Mesh& m : scene_.meshes) j_["meshes"].push_back(mesh(m));
        for (const Light& l : scene_.lights) lights_.push_back(light(l));
        json roots = json::array();
        for (int r : scene_.roots) roots.push_back(r);
        for (const Node& n : scene_.nodes) j_["nodes"].push_back(node(n));
        for (int r : scene_.roots) place_at_origin(j_["nodes"][static_cast<size_t>(r)]);
        // Cameras, in order; one not placed by a node gets a root node at its world transform.
        for (size_t i = 0; i < scene_.cameras.size(); ++i) {
            const Camera& c = scene_.cameras[i];
            j_["cameras"].push_back(camera(c));
            if (c.node >= 0 && static_cast<size_t>(c.node) < scene_.nodes.size()) {
                j_["nodes"][static_cast<size_t>(c.node)]["camera"] = i;
            } else {
                json n = {{"name", c.name}, {"camera", i}, {"matrix", vec(glm::value_ptr(c.world), 16)}};
                place_at_origin(n);
                roots.push_back(j_["nodes"].size());
                j_["nodes"].push_back(n);
            }
        }
        json scene = {{"nodes", roots}};
        if (scene_.environment.present()) {
            scene["extras"]["environment_radiance"] = vec3(scene_.environment.radiance);
            if (scene_.environment.intensity != 1.0f) scene["extras"]["environment_intensity"] = static_cast<double>(scene_.environment.intensity);
        }
        j_["scenes"] = json::array({scene});
        std::vector<std::string> used;
        if (!lights_.empty()) {
            j_["extensions"]["KHR_lights_punctual"]["lights"] = lights_;
            used.push_back("KHR_lights_punctual");
        }
        for (const std::string& e : material_extensions_) used.push_back(e);
        if (!used.empty()) j_["extensionsUsed"] = used;
        if (!bin_.empty()) j_["buffers"] = json::array({{{"byteLength", bin_.size()}, {"uri", "data:application/octet-stream;base64," + gltf::validation::base64_encode(std::string_view(reinterpret_cast<const char*>(bin_.data()), bin_.size()))}}});
        return j_;
    }

private:
    void refuse_what_is_not_written() const {
        auto refuse = [&](const std::string& what) {
            throw bad_input(scene_.source.string() + ": cannot write " + what + " to glTF (gltf_writer writes geometry, materials, lights, cameras and a constant environment)");
        };
        if (!scene_.skins.empty()) refuse("skins");
        if (!scene_.animations.empty()) refuse("animations");
        if (scene_.environment.has_map()) refuse("an environment map");
        for (const Mesh& m : scene_.meshes)
            for (const Primitive& p : m.primitives)
                if (!p.targets.empty() || p.skinned()) refuse("morph targets or skinned primitives (mesh '" + m.name + "')");
        for (const Material& m : scene_.materials)
            for (const TextureRef* t : {&m.base_color_texture, &m.metallic_roughness_texture, &m.normal_texture, &m.occlusion_texture, &m.emissive_texture})
                if (t->present()) refuse("textures (material '" + m.name + "')");
        for (const Node& n : scene_.nodes)
            if (n.reflection_probe) refuse("reflection probes (node '" + n.name + "')");
    }

    int view(const void* data, size_t bytes, int target) {
        while (bin_.size() % 4) bin_.push_back(0);
        json v = {{"buffer", 0}, {"byteOffset", bin_.size()}, {"byteLength", bytes}, {"target", target}};
        const auto* p = static_cast<const unsigned char*>(data);
        bin_.insert(bin_.end(), p, p + bytes);
        j_["bufferViews"].push_back(v);
        return static_cast<int>(j_["bufferViews"].size()) - 1;
    }
    int accessor(int view, int component, size_t count, const char* type) {
        j_["accessors"].push_back({{"bufferView", view}, {"componentType", component}, {"count", count}, {"type", type}});
        return static_cast<int>(j_["accessors"].size()) - 1;
    }

    json mesh(const Mesh& m) {
        json primitives = json::array();
        for (const Primitive& p : m.primitives) {
            if (p.vertices.empty() || p.indices.empty()) continue;
            std::vector<float> pos, nrm, uv;
            bool has_uv = false;
            glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
            for (const Vertex& v : p.vertices) {
                pos.insert(pos.end(), {v.position.x, v.position.y, v.position.z});
                nrm.insert(nrm.end(), {v.normal.x, v.normal.y, v.normal.z});
                uv.insert(uv.end(), {v.uv0.x, v.uv0.y});
                has_uv = has_uv || v.uv0 != glm::vec2(0.0f);
                lo = glm::min(lo, v.position);
                hi = glm::max(hi, v.position);
            }
            const int a_pos = accessor(view(pos.data(), pos.size() * 4, 34962), 5126, p.vertices.size(), "VEC3");
            j_["accessors"][static_cast<size_t>(a_pos)]["min"] = vec3(lo);
            j_["accessors"][static_cast<size_t>(a_pos)]["max"] = vec3(hi);
            json attributes = {{"POSITION", a_pos}, {"NORMAL", accessor(view(nrm.data(), nrm.size() * 4, 34962), 5126, p.vertices.size(), "VEC3")}};
            if (has_uv) attributes["TEXCOORD_0"] = accessor(view(uv.data(), uv.size() * 4, 34962), 5126, p.vertices.size(), "VEC2");
            json prim = {{"attributes", attributes},
                         {"indices", accessor(view(p.indices.data(), p.indices.size() * 4, 34963), 5125, p.indices.size(), "SCALAR")}};
            if (p.material >= 0) prim["material"] = p.material;
            primitives.push_back(prim);
        }
        return {{"name", m.name}, {"primitives", primitives}};
    }

    json material(const Material& m) {
        json j = {{"name", m.name},
                  {"pbrMetallicRoughness",
                   {{"baseColorFactor", vec(glm::value_ptr(m.base_color), 4)},
                    {"metallicFactor", static_cast<double>(m.metallic)},
                    {"roughnessFactor", static_cast<double>(m.roughness)}}}};
        if (m.is_emissive() || m.emissive != glm::vec3(0.0f)) j["emissiveFactor"] = vec3(m.emissive);
        auto ext = [&](const char* name, json value) {
            j["extensions"][name] = std::move(value);
            if (std::find(material_extensions_.begin(), material_extensions_.end(), name) == material_extensions_.end())
                material_extensions_.push_back(name);
        };
        if (m.emissive_strength != 1.0f) ext("KHR_materials_emissive_strength", {{"emissiveStrength", static_cast<double>(m.emissive_strength)}});
        if (m.specular_factor != 1.0f || m.specular_color != glm::vec3(1.0f))
            ext("KHR_materials_specular", {{"specularFactor", static_cast<double>(m.specular_factor)}, {"specularColorFactor", vec3(m.specular_color)}});
        if (m.ior != 1.5f) ext("KHR_materials_ior", {{"ior", static_cast<double>(m.ior)}});
        if (m.transmission != 0.0f) ext("KHR_materials_transmission", {{"transmissionFactor", static_cast<double>(m.transmission)}});
        if (m.thickness != 0.0f || m.attenuation_color != glm::vec3(1.0f) || std::isfinite(m.attenuation_distance)) {
            json v = {{"thicknessFactor", static_cast<double>(m.thickness)}, {"attenuationColor", vec3(m.attenuation_color)}};
            if (std::isfinite(m.attenuation_distance)) v["attenuationDistance"] = static_cast<double>(m.attenuation_distance);
            ext("KHR_materials_volume", v);
        }
        if (m.alpha_mode == AlphaMode::mask) j["alphaMode"] = "MASK", j["alphaCutoff"] = static_cast<double>(m.alpha_cutoff);
        if (m.alpha_mode == AlphaMode::blend) j["alphaMode"] = "BLEND";
        if (m.double_sided) j["doubleSided"] = true;
        return j;
    }

    static json light(const Light& l) {
        const char* type = l.type == LightType::directional ? "directional" : l.type == LightType::spot ? "spot" : "point";
        json j = {{"name", l.name}, {"type", type}, {"color", vec3(l.color)}, {"intensity", static_cast<double>(l.intensity)}};
        if (l.range > 0.0f && l.type != LightType::directional) j["range"] = static_cast<double>(l.range);
        if (l.type == LightType::spot)
            j["spot"] = {{"innerConeAngle", static_cast<double>(l.inner_cone)}, {"outerConeAngle", static_cast<double>(l.outer_cone)}};
        return j;
    }

    // A root node of a scene far from the file's origin (Scene::origin) gets the origin back onto
    // its translation, in double, as the file had it.
    void place_at_origin(json& node) const {
        if (scene_.origin == glm::dvec3(0.0)) return;
        if (!node.contains("matrix")) node["matrix"] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
        for (int a = 0; a < 3; ++a) node["matrix"][static_cast<size_t>(12 + a)] = node["matrix"][static_cast<size_t>(12 + a)].get<double>() + scene_.origin[a];
    }

    json node(const Node& n) const {
        json j = {{"name", n.name}};
        // The node's own transform: the rest one if apply_pose changed `local`.
        const glm::mat4 local = n.rest_local ? *n.rest_local : n.local;
        if (local != glm::mat4(1.0f)) j["matrix"] = vec(glm::value_ptr(local), 16);
        if (!n.children.empty()) j["children"] = n.children;
        if (n.mesh >= 0) j["mesh"] = n.mesh;
        if (n.light >= 0) j["extensions"]["KHR_lights_punctual"]["light"] = n.light;
        if (n.sphere_radius) j["extras"]["sphere"]["radius"] = static_cast<double>(*n.sphere_radius);
        return j;
    }

    static json camera(const Camera& c) {
        json j = {{"name", c.name}};
        if (c.orthographic) {
            j["type"] = "orthographic";
            j["orthographic"] = {{"xmag", static_cast<double>(c.xmag)}, {"ymag", static_cast<double>(c.ymag)}, {"znear", static_cast<double>(c.znear)},
                                 {"zfar", static_cast<double>(c.zfar > 0.0f ? c.zfar : 1e6f * std::max(c.znear, 1e-3f))}};
        } else {
            j["type"] = "perspective";
            json p = {{"yfov", static_cast<double>(c.yfov)}, {"znear", static_cast<double>(c.znear)}};
            if (c.zfar > 0.0f) p["zfar"] = static_cast<double>(c.zfar);
            if (c.aspect_ratio > 0.0f) p["aspectRatio"] = static_cast<double>(c.aspect_ratio);
            j["perspective"] = p;
        }
        if (c.aperture > 0.0f) j["extras"]["aperture"] = static_cast<double>(c.aperture);
        if (c.focus_distance > 0.0f) j["extras"]["focus_distance"] = static_cast<double>(c.focus_distance);
        return j;
    }

    const Scene& scene_;
    json j_;
    json lights_ = json::array();
    std::vector<std::string> material_extensions_;
    std::vector<unsigned char> bin_;
};

}  // namespace

std::string gltf_text(const Scene& scene) { return Writer(scene).build().dump(1); }

void write_gltf(const Scene& scene, const std::filesystem::path& path) {
    const std::string text = gltf_text(scene);
    if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path());
    std::ofstream out(path, std::ios::binary);
    out << text;
    if (!out) throw bad_input(path.string() + ": cannot write");
}

}  // namespace candela
