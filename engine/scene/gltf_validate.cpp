#include "scene/gltf_validate.hpp"

#include <algorithm>
#include <cstring>
#include <map>

#include "core/error.hpp"
#include "scene/gltf_validate_internal.hpp"

// The document checks are split by glTF object kind over gltf_validate_*.cpp, around the shared
// context in gltf_validate_internal.hpp; this file has the order of the checks, the top level
// (root, asset), the GLB container and the public entry points.
namespace candela::gltf {
namespace validation {
namespace {

const char* const kImplemented[] = {"KHR_lights_punctual", "KHR_materials_emissive_strength", "KHR_materials_specular",
                                    "KHR_materials_ior", "KHR_materials_transmission", "KHR_materials_volume",
                                    "KHR_texture_transform", "KHR_mesh_quantization", "KHR_materials_clearcoat",
                                    "KHR_materials_sheen", "KHR_materials_anisotropy", "KHR_materials_iridescence",
                                    "KHR_materials_unlit", "KHR_materials_pbrSpecularGlossiness", "KHR_draco_mesh_compression",
                                    "EXT_meshopt_compression", "EXT_mesh_gpu_instancing", "KHR_texture_basisu", "KHR_xmp", "KHR_xmp_json_ld",
                                    "KHR_materials_variants"};

std::string plural(const std::string& kind, size_t n) {
    static const std::map<std::string, std::string> p = {
        {"accessor", "accessors"}, {"animation", "animations"}, {"buffer", "buffers"}, {"bufferView", "bufferViews"},
        {"camera", "cameras"}, {"image", "images"}, {"material", "materials"}, {"mesh", "meshes"}, {"node", "nodes"},
        {"sampler", "samplers"}, {"scene", "scenes"}, {"skin", "skins"}, {"texture", "textures"},
        {"primitive", "mesh primitives"}, {"textureInfo", "texture references"}, {"channel target", "animation targets"}};
    if (n == 1) return kind == "textureInfo" ? "texture reference" : kind == "primitive" ? "mesh primitive" : kind;
    auto it = p.find(kind);
    return it == p.end() ? kind + " objects" : it->second;
}

}  // namespace

std::vector<Issue> Validator::run() {
    check_root();
    check_asset();
    check_extension_declarations();
    check_buffers();
    check_buffer_views();
    check_accessors();
    check_images();
    check_samplers();
    check_textures();
    check_materials();
    check_cameras();
    check_lights();
    check_meshes();
    for (size_t i = 0; i < accessors_.size(); ++i)
        if (!accessors_[i].out_of_bounds.empty() && !accessors_[i].reported) problem(at("accessors", i), accessors_[i].out_of_bounds);
    check_nodes();
    check_scenes();
    check_node_loops();
    check_skins();       // errors: what posing reads (joints, inverse bind matrices); warnings: the hierarchy
    check_animations();  // errors: what sampling reads (times, output formats and counts); warnings: the rest
    check_variants();  // errors: the variants' mappings select materials
    {
        Soft soft(*this);  // posing works without these
        check_skinned_nodes_in_scenes();
    }
    return std::move(issues_);
}

void Validator::check_root() {
    static const char* collections[] = {"accessors", "animations", "buffers", "bufferViews", "cameras", "images", "materials",
                                        "meshes", "nodes", "samplers", "scenes", "skins", "textures"};
    if (!get(d_, "asset")) problem("asset", "missing (not a glTF 2.0 file?)");
    for (const char* c : collections) {
        const json* v = get(d_, c);
        if (!v) continue;
        if (!v->is_array()) {
            problem(c, "must be an array of objects, not " + std::string(v->type_name()));
            continue;
        }
        if (v->empty()) warn(c, "is an empty array (omit it instead)");
        for (size_t i = 0; i < v->size(); ++i)
            if (!(*v)[i].is_object()) problem(at(c, i), "must be an object, not " + std::string((*v)[i].type_name()));
    }
    if (const json* s = get(d_, "scene")) ref_value(*s, "scene", "scene", count("scenes"));
}

void Validator::check_asset() {
    const json* a = get(d_, "asset");
    if (!a) return;
    if (!a->is_object()) {
        problem("asset", "must be an object");
        return;
    }
    auto version = [&](const char* key, bool required) -> std::optional<std::pair<int, int>> {
        const std::string* v = string(*a, key, "asset", required);
        if (!v) return std::nullopt;
        const size_t dot = v->find('.');
        bool ok = dot != std::string::npos && dot > 0 && dot + 1 < v->size();
        for (size_t i = 0; ok && i < v->size(); ++i) ok = i == dot || (v->at(i) >= '0' && v->at(i) <= '9');
        if (!ok || v->size() > 12) {
            problem(at("asset", key), "'" + *v + "' is not a version of the form MAJOR.MINOR");
            return std::nullopt;
        }
        return std::make_pair(std::stoi(v->substr(0, dot)), std::stoi(v->substr(dot + 1)));
    };
    const auto v = version("version", true);
    if (v && v->first != 2)
        problem("asset.version", "glTF " + std::to_string(v->first) + "." + std::to_string(v->second) +
                                     " is not supported (Candela reads glTF 2.x)");
    const auto mv = version("minVersion", false);
    if (v && mv && *mv > *v)
        problem("asset.minVersion", "minVersion " + std::to_string(mv->first) + "." + std::to_string(mv->second) +
                                        " is greater than version");
    if (mv && *mv > std::make_pair(2, 0))
        warn("asset.minVersion", "the file needs glTF " + std::to_string(mv->first) + "." + std::to_string(mv->second) +
                                        "; Candela reads glTF 2.0");
}

}  // namespace validation

namespace {

uint32_t u32(std::string_view b, size_t at) {
    uint32_t v;
    std::memcpy(&v, b.data() + at, 4);
    return v;  // glTF is little-endian, as is every platform Candela builds on
}

}  // namespace

bool buffer_available(const nlohmann::json& buffer, bool glb, size_t index) {
    using namespace validation;
    if (!buffer.is_object()) return false;
    auto uri = buffer.find("uri");
    if (uri == buffer.end()) return glb && index == 0;
    if (!uri->is_string()) return false;
    const std::string u = uri->get<std::string>();
    return starts_with(u, "data:") || uri_problem(u).empty();
}

bool extension_implemented(std::string_view name) {
    using namespace validation;
    return std::find(std::begin(kImplemented), std::end(kImplemented), name) != std::end(kImplemented);
}

// The GLB container (spec 4.4): a 12-byte header (magic "glTF", version 2, total length), then
// 8-byte-aligned chunks: JSON first, then at most one BIN.
std::string_view glb_json_chunk(const std::string& file, std::string_view& b, int64_t* bin_size, std::vector<Issue>* warnings) {
    auto fail = [&](size_t offset, const std::string& what) -> std::string_view {
        throw bad_input(file + ": GLB byte " + std::to_string(offset) + ": " + what);
    };
    constexpr uint32_t kJson = 0x4E4F534A, kBin = 0x004E4942;
    *bin_size = -1;
    if (b.size() < 12) return fail(b.size(), "the file ends inside the 12-byte header");
    if (b.compare(0, 4, "glTF") != 0) return fail(0, "the magic is not 'glTF'");
    if (u32(b, 4) != 2) return fail(4, "container version " + std::to_string(u32(b, 4)) + " is not 2");
    const uint32_t length = u32(b, 8);
    if (length < 20) return fail(8, "declared length " + std::to_string(length) + " is too small for a header and a chunk");
    if (length > b.size())
        return fail(8, "declared length " + std::to_string(length) + " but the file has " + std::to_string(b.size()) + " bytes");
    if (length < b.size()) {
        warnings->push_back({false, "", "GLB: " + std::to_string(b.size() - length) + " bytes after the declared length " +
                                            std::to_string(length) + "; ignored"});
        b = b.substr(0, length);
    }
    std::string_view json_chunk;
    bool have_json = false;
    for (size_t pos = 12; pos < b.size();) {
        if (b.size() - pos < 8) return fail(pos, "the file ends inside a chunk header");
        const uint32_t len = u32(b, pos), type = u32(b, pos + 4);
        if (len % 4 != 0) return fail(pos, "chunk length " + std::to_string(len) + " is not a multiple of 4");
        if (len > b.size() - pos - 8)
            return fail(pos, "chunk length " + std::to_string(len) + " runs past the end of the file");
        if (pos == 12 && type != kJson) return fail(pos, "the first chunk is not JSON");
        if (type == kJson) {
            if (have_json) return fail(pos, "a second JSON chunk");
            if (len == 0) return fail(pos, "the JSON chunk is empty");
            json_chunk = b.substr(pos + 8, len);
            have_json = true;
        } else if (type == kBin) {
            if (*bin_size >= 0) return fail(pos, "a second BIN chunk");
            if (!have_json || pos != 20 + json_chunk.size()) return fail(pos, "the BIN chunk must directly follow the JSON chunk");
            *bin_size = len;
        }
        pos += 8 + static_cast<size_t>(len);
    }
    return json_chunk;
}

std::vector<Issue> validate_document(const nlohmann::json& doc, bool glb, int64_t glb_bin_size) {
    return validation::Validator(doc, glb, glb_bin_size).run();
}

std::vector<IgnoredFeature> ignored_features(const nlohmann::json& doc) {
    using namespace validation;
    std::vector<IgnoredFeature> out;
    auto collection = [&](const char* key) -> const json* {
        auto it = doc.find(key);
        return it != doc.end() && it->is_array() && !it->empty() ? &*it : nullptr;
    };
    auto counted = [](size_t n, const char* one, const char* many) { return std::to_string(n) + " " + (n == 1 ? one : many); };
    // Skins, animations and POSITION/NORMAL/TANGENT morph targets are implemented;
    // morph targets of texture coordinates or colours are not.
    if (const json* meshes = collection("meshes")) {
        size_t n = 0;
        std::string first;
        for (size_t mi = 0; mi < meshes->size(); ++mi) {
            const json& m = (*meshes)[mi];
            if (!m.is_object() || !m.contains("primitives") || !m["primitives"].is_array()) continue;
            bool morphed = false;
            for (size_t pi = 0; pi < m["primitives"].size(); ++pi) {
                const json& p = m["primitives"][pi];
                if (!p.is_object() || !p.contains("targets") || !p["targets"].is_array()) continue;
                for (size_t ti = 0; ti < p["targets"].size(); ++ti) {
                    const json& t = p["targets"][ti];
                    if (!t.is_object()) continue;
                    for (auto it = t.begin(); it != t.end(); ++it)
                        if (set_index(it.key(), "TEXCOORD_") >= 0 || set_index(it.key(), "COLOR_") >= 0) {
                            if (first.empty()) first = at(at(at(at(at("meshes", mi), "primitives"), pi), "targets"), ti) + "." + it.key();
                            morphed = true;
                        }
                }
            }
            n += morphed;
        }
        if (n) out.push_back({"morph targets of texture coordinates or colours on " + counted(n, "mesh", "meshes"), first});
    }
    // Extensions: every object carrying one Candela does not implement, counted per kind.
    struct Use {
        std::string first;
        std::map<std::string, size_t> kinds;
    };
    std::map<std::string, Use> uses;
    size_t texcoord2 = 0;
    std::string texcoord2_first;
    walk(doc, "", "root", [&](const json& obj, const std::string& path, const std::string& kind) {
        if (kind == "textureInfo") {
            int64_t set = 0;
            if (auto tc = obj.find("texCoord"); tc != obj.end() && tc->is_number_integer()) set = tc->get<int64_t>();
            if (auto e = obj.find("extensions"); e != obj.end() && e->is_object())
                if (auto tt = e->find("KHR_texture_transform"); tt != e->end() && tt->is_object())
                    if (auto tc = tt->find("texCoord"); tc != tt->end() && tc->is_number_integer()) set = tc->get<int64_t>();
            if (set >= 2 && !texcoord2++) texcoord2_first = path;
        }
        auto e = obj.find("extensions");
        if (e == obj.end() || !e->is_object()) return;
        for (auto it = e->begin(); it != e->end(); ++it) {
            if (extension_implemented(it.key())) continue;
            Use& u = uses[it.key()];
            if (u.first.empty()) u.first = at(at(path, "extensions"), it.key());
            ++u.kinds[kind];
        }
    });
    if (auto used = doc.find("extensionsUsed"); used != doc.end() && used->is_array())
        for (size_t i = 0; i < used->size(); ++i)
            if ((*used)[i].is_string() && !extension_implemented((*used)[i].get<std::string>()))
                if (Use& u = uses[(*used)[i].get<std::string>()]; u.first.empty()) u.first = at("extensionsUsed", i);
    for (const auto& [name, u] : uses) {
        std::string phrase = name;
        std::string sep = " on ";
        for (const auto& [kind, n] : u.kinds) {
            phrase += sep + (kind == "root" ? std::string("the top level") : std::to_string(n) + " " + plural(kind, n));
            sep = " and ";
        }
        if (u.kinds.empty()) phrase += " (declared in extensionsUsed)";
        out.push_back({phrase, u.first});
    }
    if (texcoord2)
        out.push_back({"texture coordinate sets above 1 on " + std::to_string(texcoord2) + (texcoord2 == 1 ? " texture reference" : " texture references"),
                       texcoord2_first});
    return out;
}

}  // namespace candela::gltf
