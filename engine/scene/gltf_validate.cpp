#include "scene/gltf_validate.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <cctype>

#include "core/error.hpp"

// Rules: the glTF 2.0 specification (Khronos, 2021), sections 3.6-3.12 and 5 (Properties
// Reference), and the specifications of the KHR extensions named below. Codes in comments are
// glTF-Validator's issue codes for the same rule, to make the mapping easy to audit.
namespace candela::gltf {
namespace {

using json = nlohmann::json;

std::string at(const std::string& base, const std::string& key) { return base.empty() ? key : base + "." + key; }
std::string at(const std::string& base, size_t i) { return base + "[" + std::to_string(i) + "]"; }

std::string num(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", v);
    return buf;
}

constexpr double kPi = 3.14159265358979323846;

constexpr int kByte = 5120, kUByte = 5121, kShort = 5122, kUShort = 5123, kUInt = 5125, kFloat = 5126;
constexpr int64_t kArrayBuffer = 34962, kElementArrayBuffer = 34963;

int component_size(int64_t ct) {
    switch (ct) {
        case kByte: case kUByte: return 1;
        case kShort: case kUShort: return 2;
        case kUInt: case kFloat: return 4;
        default: return 0;
    }
}

const char* component_name(int64_t ct) {
    switch (ct) {
        case kByte: return "BYTE";
        case kUByte: return "UNSIGNED_BYTE";
        case kShort: return "SHORT";
        case kUShort: return "UNSIGNED_SHORT";
        case kUInt: return "UNSIGNED_INT";
        case kFloat: return "FLOAT";
        default: return "?";
    }
}

int type_components(const std::string& t) {
    if (t == "SCALAR") return 1;
    if (t == "VEC2") return 2;
    if (t == "VEC3") return 3;
    if (t == "VEC4" || t == "MAT2") return 4;
    if (t == "MAT3") return 9;
    if (t == "MAT4") return 16;
    return 0;
}

// Bytes of one element: matrix columns start on 4-byte boundaries (spec 3.6.2.4, data alignment).
int64_t element_size(int64_t ct, const std::string& type) {
    const int c = component_size(ct);
    if (type == "MAT2" && c == 1) return 8;
    if (type == "MAT3" && c == 1) return 12;
    if (type == "MAT3" && c == 2) return 24;
    return static_cast<int64_t>(c) * type_components(type);
}

bool starts_with(std::string_view s, std::string_view p) { return s.substr(0, p.size()) == p; }
bool ends_with(std::string_view s, std::string_view p) { return s.size() >= p.size() && s.substr(s.size() - p.size()) == p; }

// "TEXCOORD_3" -> 3 for prefix "TEXCOORD_"; -1 if `name` is not prefix + a set index (no leading zeros).
int set_index(const std::string& name, const char* prefix) {
    const size_t n = std::strlen(prefix);
    if (name.size() <= n || name.compare(0, n, prefix) != 0) return -1;
    const std::string digits = name.substr(n);
    if (digits.size() > 6 || (digits.size() > 1 && digits[0] == '0')) return -1;
    for (char ch : digits)
        if (ch < '0' || ch > '9') return -1;
    return std::stoi(digits);
}

bool valid_base64(std::string_view s, size_t* decoded) {
    if (s.size() % 4 != 0) return false;
    size_t pad = 0;
    for (size_t i = 0; i < s.size(); ++i) {
        const char ch = s[i];
        const bool alpha = (ch >= 'A' && ch <= 'Z') || (ch >= 'a' && ch <= 'z') || (ch >= '0' && ch <= '9') || ch == '+' || ch == '/';
        if (ch == '=') {
            if (i + 2 < s.size()) return false;
            ++pad;
        } else if (!alpha || pad) {
            return false;
        }
    }
    *decoded = s.size() / 4 * 3 - pad;
    return true;
}

// The size of a data URI's non-base64 payload (RFC 2397: percent-encoded octets).
bool percent_decoded_size(std::string_view s, size_t* decoded) {
    size_t n = 0;
    for (size_t i = 0; i < s.size(); ++i, ++n)
        if (s[i] == '%') {
            if (i + 2 >= s.size() || !std::isxdigit(static_cast<unsigned char>(s[i + 1])) || !std::isxdigit(static_cast<unsigned char>(s[i + 2])))
                return false;
            i += 2;
        }
    *decoded = n;
    return true;
}

// A data: URI "data:[<media type>][;base64],<data>": its media type and base64 payload.
struct DataUri {
    std::string media_type;
    std::string_view payload;
    bool base64 = false;
};
std::optional<DataUri> parse_data_uri(std::string_view uri) {
    if (!starts_with(uri, "data:")) return std::nullopt;
    const size_t comma = uri.find(',');
    if (comma == std::string_view::npos) return DataUri{};
    DataUri d;
    std::string_view head = uri.substr(5, comma - 5);
    if (ends_with(head, ";base64")) {
        d.base64 = true;
        head.remove_suffix(7);
    }
    d.media_type = std::string(head.substr(0, head.find(';')));
    d.payload = uri.substr(comma + 1);
    return d;
}

// A URI that is not data: must be a relative reference (RFC 3986): a scheme ends at the first
// ':' before any '/', '?' or '#'.
std::string uri_problem(std::string_view uri) {
    const size_t stop = uri.find_first_of("/?#");
    const size_t colon = uri.find(':');
    if (colon == std::string_view::npos || (stop != std::string_view::npos && stop < colon)) return {};
    const std::string_view scheme = uri.substr(0, colon);
    bool ok = !scheme.empty() && std::isalpha(static_cast<unsigned char>(scheme[0]));
    for (char ch : scheme) ok = ok && (std::isalnum(static_cast<unsigned char>(ch)) || ch == '+' || ch == '-' || ch == '.');
    if (!ok) return "'" + std::string(uri) + "' is not a valid URI";
    return "URI scheme '" + std::string(scheme) + "' is not supported (only relative paths and data: URIs)";
}

// ---- The object kinds, and where each known extension may appear (each extension's spec) ----

// The kind of a JSON object reached by `key` from an object of kind `parent`.
std::string child_kind(const std::string& parent, const std::string& key) {
    static const std::map<std::string, std::string> root = {
        {"accessors", "accessor"}, {"animations", "animation"}, {"buffers", "buffer"}, {"bufferViews", "bufferView"},
        {"cameras", "camera"}, {"images", "image"}, {"materials", "material"}, {"meshes", "mesh"}, {"nodes", "node"},
        {"samplers", "sampler"}, {"scenes", "scene"}, {"skins", "skin"}, {"textures", "texture"}, {"asset", "asset"}};
    if (parent == "root") {
        auto it = root.find(key);
        return it == root.end() ? "other" : it->second;
    }
    if (parent == "material" && key == "pbrMetallicRoughness") return "pbrMetallicRoughness";
    if ((parent == "material" || parent == "pbrMetallicRoughness" || parent == "extension") && ends_with(key, "Texture"))
        return "textureInfo";
    if (parent == "mesh" && key == "primitives") return "primitive";
    if (parent == "animation" && key == "channels") return "channel";
    if (parent == "animation" && key == "samplers") return "animation sampler";
    if (parent == "channel" && key == "target") return "channel target";
    if (parent == "accessor" && key == "sparse") return "sparse";
    if (parent == "camera" && (key == "perspective" || key == "orthographic")) return key;
    if (parent == "extension") return "extension";
    return "other";
}

// Visits every object that can carry `extensions`, with its kind; `extras` are not entered.
void walk(const json& v, const std::string& path, const std::string& kind,
          const std::function<void(const json&, const std::string&, const std::string&)>& visit) {
    if (v.is_object()) {
        visit(v, path, kind);
        for (auto it = v.begin(); it != v.end(); ++it) {
            if (it.key() == "extras") continue;
            if (it.key() == "extensions" && it->is_object()) {
                for (auto e = it->begin(); e != it->end(); ++e)
                    walk(*e, at(at(path, "extensions"), e.key()), "extension", visit);
                continue;
            }
            walk(*it, at(path, it.key()), child_kind(kind, it.key()), visit);
        }
    } else if (v.is_array()) {
        for (size_t i = 0; i < v.size(); ++i) walk(v[i], at(path, i), kind, visit);
    }
}

// Object kinds an extension is defined on, per its specification; empty: not checked.
std::vector<std::string> allowed_kinds(const std::string& ext) {
    if (ext == "KHR_lights_punctual") return {"root", "node"};
    if (ext == "KHR_materials_variants") return {"root", "primitive"};
    if (starts_with(ext, "KHR_materials_")) return {"material"};
    if (ext == "KHR_texture_transform") return {"textureInfo"};
    if (ext == "KHR_texture_basisu" || ext == "EXT_texture_webp" || ext == "EXT_texture_avif" || ext == "MSFT_texture_dds")
        return {"texture"};
    if (ext == "KHR_draco_mesh_compression") return {"primitive"};
    if (ext == "EXT_meshopt_compression") return {"buffer", "bufferView"};
    if (ext == "EXT_mesh_gpu_instancing" || ext == "KHR_node_visibility") return {"node"};
    if (ext == "KHR_animation_pointer") return {"channel target"};
    if (ext == "KHR_mesh_quantization") return {"(none)"};
    return {};
}

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

// Value ranges of the material extensions Candela does not implement (the loader range-checks
// the ones it does). From each extension's JSON schema.
struct Range {
    const char* ext;
    const char* key;
    double lo, hi;
    bool lo_exclusive;
};
constexpr double kInf = std::numeric_limits<double>::infinity();
const Range kExtensionRanges[] = {
    {"KHR_materials_anisotropy", "anisotropyStrength", 0, 1, false},
    {"KHR_materials_clearcoat", "clearcoatFactor", 0, 1, false},
    {"KHR_materials_clearcoat", "clearcoatRoughnessFactor", 0, 1, false},
    {"KHR_materials_dispersion", "dispersion", 0, kInf, false},
    {"KHR_materials_iridescence", "iridescenceFactor", 0, 1, false},
    {"KHR_materials_iridescence", "iridescenceIor", 1, kInf, false},
    {"KHR_materials_iridescence", "iridescenceThicknessMinimum", 0, kInf, false},
    {"KHR_materials_iridescence", "iridescenceThicknessMaximum", 0, kInf, false},
    {"KHR_materials_sheen", "sheenColorFactor", 0, 1, false},
    {"KHR_materials_sheen", "sheenRoughnessFactor", 0, 1, false},
    {"KHR_materials_diffuse_transmission", "diffuseTransmissionFactor", 0, 1, false},
    {"KHR_materials_pbrSpecularGlossiness", "diffuseFactor", 0, 1, false},
    {"KHR_materials_pbrSpecularGlossiness", "specularFactor", 0, 1, false},
    {"KHR_materials_pbrSpecularGlossiness", "glossinessFactor", 0, 1, false},
};

const char* const kImplemented[] = {"KHR_lights_punctual", "KHR_materials_emissive_strength", "KHR_materials_specular",
                                    "KHR_materials_ior", "KHR_materials_transmission", "KHR_materials_volume",
                                    "KHR_texture_transform", "KHR_mesh_quantization"};

// ---------------------------------------------------------------------------------------------

struct AccessorInfo {
    bool ok = false;  // structurally valid: the fields below can be trusted
    int64_t component_type = 0;
    std::string type;
    int components = 0;
    bool normalized = false;
    int64_t count = 0;
    int64_t view = -1;
    int64_t offset = 0;
    bool has_min = false, has_max = false;
    bool unknown_format = false;  // a type or componentType outside glTF's lists: nothing can read it
    std::string out_of_bounds;    // why its data does not fit its bufferView; reported where it is used
    bool reported = false;
    bool unavailable = false;     // its data lies in a buffer Candela cannot get (see buffer_available)
};

struct ViewInfo {
    bool ok = false;
    bool unavailable = false;
    int64_t buffer = -1, offset = 0, length = 0, stride = 0, target = 0;
};

class Validator {
public:
    Validator(const json& doc, bool glb, int64_t bin) : d_(doc), glb_(glb), bin_(bin) {}

    std::vector<Issue> run() {
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
        {
            Soft soft(*this);  // posing works without these
            check_skinned_nodes_in_scenes();
            check_variants();
        }
        return std::move(issues_);
    }

private:
    // Problems in data Candela ignores are warnings while a Soft is alive.
    struct Soft {
        explicit Soft(Validator& v) : v_(v) { ++v_.soft_; }
        ~Soft() { --v_.soft_; }
        Validator& v_;
    };
    void problem(const std::string& path, const std::string& what) { issues_.push_back({soft_ == 0, path, what}); }
    void warn(const std::string& path, const std::string& what) { issues_.push_back({false, path, what}); }
    // An error even while a Soft is alive (skins, animations and morph targets are implemented:
    // data that posing cannot use is bad input).
    void error(const std::string& path, const std::string& what) { issues_.push_back({true, path, what}); }

    const json* get(const json& obj, const char* key) const {
        if (!obj.is_object()) return nullptr;
        auto it = obj.find(key);
        return it == obj.end() ? nullptr : &*it;
    }
    size_t count(const char* collection) const {
        const json* c = get(d_, collection);
        return c && c->is_array() ? c->size() : 0;
    }
    // The objects of a top-level collection (non-objects were reported by check_root).
    std::vector<std::pair<size_t, const json*>> items(const char* collection) const {
        std::vector<std::pair<size_t, const json*>> out;
        const json* c = get(d_, collection);
        if (!c || !c->is_array()) return out;
        for (size_t i = 0; i < c->size(); ++i)
            if ((*c)[i].is_object()) out.emplace_back(i, &(*c)[i]);
        return out;
    }
    const json* item(const char* collection, int64_t i) const {
        const json* c = get(d_, collection);
        if (!c || !c->is_array() || i < 0 || static_cast<size_t>(i) >= c->size() || !(*c)[static_cast<size_t>(i)].is_object())
            return nullptr;
        return &(*c)[static_cast<size_t>(i)];
    }

    // A reference: a non-negative integer below `n`. Returns -1 when absent or invalid (reported).
    // JSON has one number type: 1.0 is the integer 1 (glTF-Validator accepts it too).
    static bool integral(const json& v) {
        return v.is_number_integer() || (v.is_number_float() && std::isfinite(v.get<double>()) && std::floor(v.get<double>()) == v.get<double>() &&
                                         std::fabs(v.get<double>()) < 9e15);
    }
    int64_t ref_value(const json& v, const std::string& path, const std::string& what, size_t n) {
        if (!integral(v) || v.get<double>() < 0) {
            problem(path, "must be a non-negative integer index, not " + v.dump());
            return -1;
        }
        if (v.get<double>() >= static_cast<double>(n)) {
            problem(path, what + " " + v.dump() + " does not exist (the file has " + std::to_string(n) + ")");
            return -1;
        }
        return static_cast<int64_t>(v.get<double>());
    }
    int64_t ref(const json& obj, const char* key, const std::string& path, const char* collection, bool required,
                const char* what = nullptr) {
        const json* v = get(obj, key);
        if (!v) {
            if (required) problem(path, std::string("'") + key + "' is required");
            return -1;
        }
        std::string w = what ? what : collection;
        if (!what && w.size() > 1) w = w == "meshes" ? "mesh" : w.substr(0, w.size() - 1);
        return ref_value(*v, at(path, key), w, count(collection));
    }
    std::optional<double> number(const json& obj, const char* key, const std::string& path, bool required) {
        const json* v = get(obj, key);
        if (!v) {
            if (required) problem(path, std::string("'") + key + "' is required");
            return std::nullopt;
        }
        if (!v->is_number()) {
            problem(at(path, key), "must be a number, not " + v->dump());
            return std::nullopt;
        }
        return v->get<double>();
    }
    std::optional<int64_t> integer(const json& obj, const char* key, const std::string& path, bool required, int64_t lo,
                                   int64_t hi = std::numeric_limits<int64_t>::max()) {
        const json* v = get(obj, key);
        if (!v) {
            if (required) problem(path, std::string("'") + key + "' is required");
            return std::nullopt;
        }
        if (!integral(*v)) {
            problem(at(path, key), "must be an integer, not " + v->dump());
            return std::nullopt;
        }
        if (v->is_number_float()) {
            const auto i = static_cast<int64_t>(v->get<double>());
            if (i >= lo && i <= hi) return i;
            problem(at(path, key), std::to_string(i) + " is out of range");
            return std::nullopt;
        }
        const int64_t i = v->is_number_unsigned() && v->get<uint64_t>() > uint64_t(std::numeric_limits<int64_t>::max())
                              ? std::numeric_limits<int64_t>::max() : v->get<int64_t>();
        if (i < lo || i > hi) {
            problem(at(path, key), std::to_string(i) + " is out of range [" + std::to_string(lo) + ", " +
                                       (hi == std::numeric_limits<int64_t>::max() ? std::string("inf") : std::to_string(hi)) + "]");
            return std::nullopt;
        }
        return i;
    }
    const std::string* string(const json& obj, const char* key, const std::string& path, bool required) {
        const json* v = get(obj, key);
        if (!v) {
            if (required) problem(path, std::string("'") + key + "' is required");
            return nullptr;
        }
        if (!v->is_string()) {
            problem(at(path, key), "must be a string, not " + v->dump());
            return nullptr;
        }
        return v->get_ptr<const std::string*>();
    }
    // An array of `n` numbers (n = 0: any length >= 1).
    const json* numbers(const json& obj, const char* key, const std::string& path, size_t n) {
        const json* v = get(obj, key);
        if (!v) return nullptr;
        if (!v->is_array() || (n && v->size() != n) || v->empty()) {
            problem(at(path, key), "must be an array of " + (n ? std::to_string(n) + " " : std::string()) + "numbers");
            return nullptr;
        }
        for (size_t i = 0; i < v->size(); ++i)
            if (!(*v)[i].is_number()) {
                problem(at(at(path, key), i), "must be a number, not " + (*v)[i].dump());
                return nullptr;
            }
        return v;
    }
    // An array of unique references; returns the valid ones.
    std::vector<int64_t> ref_array(const json& obj, const char* key, const std::string& path, const char* collection,
                                   const std::string& what, bool required) {
        std::vector<int64_t> out;
        const json* v = get(obj, key);
        if (!v) {
            if (required) problem(path, std::string("'") + key + "' is required");
            return out;
        }
        const std::string p = at(path, key);
        if (!v->is_array()) {
            problem(p, "must be an array of indices");
            return out;
        }
        if (v->empty()) warn(p, "is an empty array (omit it instead)");
        std::set<int64_t> seen;
        for (size_t i = 0; i < v->size(); ++i) {
            const int64_t r = ref_value((*v)[i], at(p, i), what, count(collection));
            if (r < 0) continue;
            if (!seen.insert(r).second) problem(at(p, i), what + " " + std::to_string(r) + " is listed twice");
            else out.push_back(r);
        }
        return out;
    }

    bool used(const std::string& ext) const { return used_.count(ext) > 0; }

    // ---- root ----
    void check_root() {
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

    void check_asset() {
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

    // extensionsUsed / extensionsRequired, and every `extensions` object in the file.
    void check_extension_declarations() {
        for (const char* key : {"extensionsUsed", "extensionsRequired"}) {
            const json* v = get(d_, key);
            if (!v) continue;
            if (!v->is_array()) {
                problem(key, "must be an array of strings");
                continue;
            }
            std::set<std::string> seen;
            for (size_t i = 0; i < v->size(); ++i) {
                if (!(*v)[i].is_string()) {
                    problem(at(key, i), "must be a string");
                    continue;
                }
                const std::string name = (*v)[i].get<std::string>();
                if (!seen.insert(name).second) warn(at(key, i), "'" + name + "' is listed twice");
                if (std::strcmp(key, "extensionsUsed") == 0) used_.insert(name);
                else if (!used_.count(name)) warn(at(key, i), "'" + name + "' is required but not in extensionsUsed");
            }
            if (v->empty()) warn(key, "is an empty array (omit it instead)");
        }
        if (used("KHR_mesh_quantization")) {
            const json* r = get(d_, "extensionsRequired");
            bool required = false;
            if (r && r->is_array())
                for (const auto& e : *r) required = required || (e.is_string() && e.get<std::string>() == "KHR_mesh_quantization");
            if (!required) warn("extensionsUsed", "KHR_mesh_quantization must also be in extensionsRequired");
        }
        std::set<std::string> undeclared;
        walk(d_, "", "root", [&](const json& obj, const std::string& path, const std::string& kind) {
            const json* ext = get(obj, "extensions");
            if (!ext) return;
            const std::string epath = at(path, "extensions");
            if (!ext->is_object()) {
                problem(epath, "must be an object");
                return;
            }
            for (auto it = ext->begin(); it != ext->end(); ++it) {
                const std::string& name = it.key();
                const std::string p = at(epath, name);
                std::optional<Soft> soft;
                if (!extension_implemented(name)) soft.emplace(*this);
                if (!it->is_object()) problem(p, "must be an object, not " + std::string(it->type_name()));
                if (!used(name) && undeclared.insert(name).second) warn(p, "'" + name + "' is not declared in extensionsUsed");
                const auto kinds = allowed_kinds(name);
                if (!kinds.empty() && std::find(kinds.begin(), kinds.end(), kind) == kinds.end())
                    warn(p, name + " is not defined on " +
                                (kind == "root" ? std::string("the top level") : (std::strchr("aeiou", kind[0]) ? "an " : "a ") + kind) + "; ignored");
                else if (starts_with(name, "KHR_materials_") && it->is_object())
                    for (const Range& r : kExtensionRanges) {
                        if (name != r.ext) continue;
                        const json* v = get(*it, r.key);
                        if (!v) continue;
                        auto check = [&](const json& x, const std::string& xp) {
                            if (!x.is_number()) return problem(xp, "must be a number");
                            const double d = x.get<double>();
                            if (d < r.lo || d > r.hi || (r.lo_exclusive && d == r.lo))
                                problem(xp, num(d) + " is out of range [" + num(r.lo) + ", " + num(r.hi) + "]");
                        };
                        if (v->is_array()) for (size_t i = 0; i < v->size(); ++i) check((*v)[i], at(at(p, r.key), i));
                        else check(*v, at(p, r.key));
                    }
            }
        });
    }

    // ---- buffers, bufferViews, accessors ----
    void check_buffers() {
        buffer_len_.assign(count("buffers"), -1);
        for (auto [i, b] : items("buffers")) {
            const std::string p = at("buffers", i);
            const auto len = integer(*b, "byteLength", p, true, 1);
            if (len) buffer_len_[i] = *len;
            const std::string* uri = string(*b, "uri", p, false);
            if (uri) {
                if (auto data = parse_data_uri(*uri)) {
                    size_t decoded = 0;
                    if (data->media_type != "application/octet-stream" && data->media_type != "application/gltf-buffer")
                        problem(at(p, "uri"), "data URI media type must be application/octet-stream or application/gltf-buffer, not '" +
                                                  data->media_type + "'");
                    else if (data->base64 ? !valid_base64(data->payload, &decoded) : !percent_decoded_size(data->payload, &decoded))
                        problem(at(p, "uri"), "is not a valid data URI");
                    else if (len && static_cast<int64_t>(decoded) != *len)
                        problem(p, "the data URI holds " + std::to_string(decoded) + " bytes but byteLength is " + std::to_string(*len));
                } else if (const std::string why = uri_problem(*uri); !why.empty()) {
                    if (why.find("not supported") == std::string::npos) problem(at(p, "uri"), why);
                    else {
                        warn(at(p, "uri"), why + "; its data is not available");
                        unavailable_buffers_.insert(i);
                    }
                }
            } else if (!get(*b, "uri")) {
                if (!glb_ || i != 0) {
                    warn(p, "has no uri and is not a .glb's BIN chunk; its data is not available");
                    unavailable_buffers_.insert(i);
                } else if (bin_ < 0) {
                    problem(p, "refers to the .glb's BIN chunk, but the file has none");
                } else if (len && bin_ < *len) {
                    problem(p, "byteLength " + std::to_string(*len) + " is larger than the BIN chunk (" + std::to_string(bin_) + " bytes)");
                } else if (len && bin_ - *len > 3) {
                    warn(p, "the BIN chunk has " + std::to_string(bin_) + " bytes, more than byteLength " + std::to_string(*len) + " + padding");
                }
            }
        }
    }

    void check_buffer_views() {
        views_.assign(count("bufferViews"), ViewInfo{});
        for (auto [i, v] : items("bufferViews")) {
            const std::string p = at("bufferViews", i);
            ViewInfo& info = views_[i];
            info.buffer = ref(*v, "buffer", p, "buffers", true);
            info.unavailable = unavailable_buffers_.count(static_cast<size_t>(std::max<int64_t>(info.buffer, 0))) && info.buffer >= 0;
            const auto offset = integer(*v, "byteOffset", p, false, 0);
            const auto length = integer(*v, "byteLength", p, true, 1);
            const auto stride = integer(*v, "byteStride", p, false, 4, 252);
            const auto target = integer(*v, "target", p, false, 0);
            if (stride && *stride % 4 != 0) problem(at(p, "byteStride"), std::to_string(*stride) + " is not a multiple of 4");
            if (target && *target != kArrayBuffer && *target != kElementArrayBuffer)
                warn(at(p, "target"), std::to_string(*target) + " is neither ARRAY_BUFFER (34962) nor ELEMENT_ARRAY_BUFFER (34963)");
            if (!length || info.buffer < 0 || (get(*v, "byteOffset") && !offset)) continue;
            info.offset = offset.value_or(0);
            info.length = *length;
            info.stride = stride.value_or(0);
            info.target = target.value_or(0);
            const int64_t blen = buffer_len_[static_cast<size_t>(info.buffer)];
            if (blen >= 0 && (info.offset > blen || info.length > blen - info.offset)) {
                problem(at(p, "byteLength"), "byteOffset " + std::to_string(info.offset) + " + byteLength " + std::to_string(info.length) +
                                                 " exceeds buffers[" + std::to_string(info.buffer) + "].byteLength " + std::to_string(blen));
                continue;
            }
            if (info.stride > info.length)
                problem(at(p, "byteStride"), std::to_string(info.stride) + " is greater than byteLength " + std::to_string(info.length));
            if (info.stride && info.target == kElementArrayBuffer)
                problem(at(p, "byteStride"), "an index buffer view (target 34963) cannot have a byteStride");
            info.ok = !(get(*v, "byteStride") && !stride) && info.stride <= info.length;
        }
    }

    // Bounds of `count` elements of `elem` bytes at `offset` in view `view` with `stride` (0 = packed).
    void check_fits(int64_t view, int64_t offset, int64_t elem, int64_t stride, int64_t n, int64_t csize, const std::string& path,
                    int64_t last_elem = -1) {
        if (view < 0 || !views_[static_cast<size_t>(view)].ok || n <= 0 || elem <= 0) return;
        const ViewInfo& v = views_[static_cast<size_t>(view)];
        if (csize > 0 && offset % csize != 0)
            problem(at(path, "byteOffset"), std::to_string(offset) + " is not a multiple of the component size " + std::to_string(csize));
        else if (csize > 0 && (v.offset + offset) % csize != 0)
            problem(path, "bufferView byteOffset + byteOffset (" + std::to_string(v.offset + offset) +
                              ") is not a multiple of the component size " + std::to_string(csize));
        const int64_t s = stride ? stride : elem;
        // The last element needs no padding after its last matrix column.
        const long double need = static_cast<long double>(offset) + static_cast<long double>(s) * static_cast<long double>(n - 1) +
                                 (last_elem >= 0 ? last_elem : elem);
        if (need > static_cast<long double>(v.length)) {
            const std::string what = "accessor reads past the end of bufferView " + std::to_string(view) + " (needs " +
                                     num(static_cast<double>(need)) + " bytes from offset " + std::to_string(offset) + ", the view has " +
                                     std::to_string(v.length) + ")";
            if (out_of_bounds) *out_of_bounds = what;
            else problem(path, what);
        }
    }
    // Set while checking an accessor's own data: the problem is reported where the accessor is
    // used (a mesh attribute names the primitive), or at the accessor when nothing reads it.
    std::string* out_of_bounds = nullptr;

    void check_accessors() {
        static const std::set<int64_t> types = {kByte, kUByte, kShort, kUShort, kUInt, kFloat};
        accessors_.assign(count("accessors"), AccessorInfo{});
        for (auto [i, a] : items("accessors")) {
            const std::string p = at("accessors", i);
            AccessorInfo& info = accessors_[i];
            bool ok = true;
            info.view = ref(*a, "bufferView", p, "bufferViews", false);
            ok = ok && !(get(*a, "bufferView") && info.view < 0);
            info.unavailable = info.view >= 0 && views_[static_cast<size_t>(info.view)].unavailable;
            const auto offset = integer(*a, "byteOffset", p, false, 0);
            if (get(*a, "byteOffset") && !get(*a, "bufferView")) problem(at(p, "byteOffset"), "is set but there is no bufferView");
            const auto ct = integer(*a, "componentType", p, true, 0);
            // An unknown enum value is not an error by itself (glTF-Validator: VALUE_NOT_IN_LIST is a
            // warning); reading such an accessor is (see unusable()).
            if (ct && !types.count(*ct)) {
                warn(at(p, "componentType"), std::to_string(*ct) + " is not a glTF component type; the accessor is unusable");
                info.unknown_format = true;
                ok = false;
            }
            const std::string* type = string(*a, "type", p, true);
            if (type && !type_components(*type)) {
                warn(at(p, "type"), "'" + *type + "' is not SCALAR, VEC2, VEC3, VEC4, MAT2, MAT3 or MAT4; the accessor is unusable");
                info.unknown_format = true;
                ok = false;
            }
            const auto n = integer(*a, "count", p, true, 1);
            bool normalized = false;
            if (const json* nv = get(*a, "normalized")) {
                if (!nv->is_boolean()) problem(at(p, "normalized"), "must be true or false");
                else normalized = nv->get<bool>();
            }
            if (!ct || !type || !n || (get(*a, "byteOffset") && !offset) || !ok) continue;
            info.component_type = *ct;
            info.type = *type;
            info.components = type_components(*type);
            info.normalized = normalized;
            info.count = *n;
            info.offset = offset.value_or(0);
            if (normalized && (*ct == kFloat || *ct == kUInt)) {
                problem(at(p, "normalized"), std::string("only BYTE, UNSIGNED_BYTE, SHORT and UNSIGNED_SHORT can be normalized, not ") +
                                                 component_name(*ct));
                continue;
            }
            for (const char* key : {"min", "max"})
                if (const json* mm = numbers(*a, key, p, static_cast<size_t>(info.components))) {
                    (std::strcmp(key, "min") == 0 ? info.has_min : info.has_max) = true;
                    (void)mm;
                }
            const int64_t csize = component_size(*ct);
            const int64_t elem = element_size(*ct, *type);
            if ((*type == "MAT2" || *type == "MAT3") && csize < 4 && info.offset % 4 != 0)
                problem(at(p, "byteOffset"), "matrix accessors must start on a 4-byte boundary");
            if (info.view >= 0 && views_[static_cast<size_t>(info.view)].ok) {
                const ViewInfo& v = views_[static_cast<size_t>(info.view)];
                if (v.stride && v.stride < elem) {
                    problem(p, "bufferView " + std::to_string(info.view) + " byteStride " + std::to_string(v.stride) +
                                   " is smaller than the element (" + std::to_string(elem) + " bytes)");
                    continue;
                }
                const size_t before = issues_.size();
                const int64_t rows = *type == "MAT2" ? 2 : *type == "MAT3" ? 3 : 0;
                const int64_t last = rows ? elem - (elem / rows - rows * csize) : elem;
                out_of_bounds = &info.out_of_bounds;
                check_fits(info.view, info.offset, elem, v.stride, info.count, csize, p, last);
                out_of_bounds = nullptr;
                if (issues_.size() != before) continue;
            }
            if (const json* s = get(*a, "sparse")) {
                const std::string sp = at(p, "sparse");
                if (!s->is_object()) {
                    problem(sp, "must be an object");
                    continue;
                }
                const auto sn = integer(*s, "count", sp, true, 1);
                if (sn && *sn > info.count)
                    problem(at(sp, "count"), std::to_string(*sn) + " is more than the accessor's count " + std::to_string(info.count));
                for (const char* part : {"indices", "values"}) {
                    const json* o = get(*s, part);
                    const std::string pp = at(sp, part);
                    if (!o || !o->is_object()) {
                        problem(sp, std::string("'") + part + "' must be an object");
                        continue;
                    }
                    const int64_t view = ref(*o, "bufferView", pp, "bufferViews", true);
                    const auto off = integer(*o, "byteOffset", pp, false, 0);
                    int64_t e = elem, cs = csize;
                    if (std::strcmp(part, "indices") == 0) {
                        const auto ict = integer(*o, "componentType", pp, true, 0);
                        if (ict && *ict != kUByte && *ict != kUShort && *ict != kUInt) {
                            problem(at(pp, "componentType"), std::string(component_name(*ict)) + " is not an index type (UNSIGNED_BYTE, _SHORT or _INT)");
                            continue;
                        }
                        if (!ict) continue;
                        e = cs = component_size(*ict);
                    }
                    if (view >= 0 && views_[static_cast<size_t>(view)].stride)
                        problem(at(pp, "bufferView"), "bufferView " + std::to_string(view) + " of sparse data cannot have a byteStride");
                    if (sn && *sn <= info.count) check_fits(view, off.value_or(0), e, 0, *sn, cs, pp);
                }
            }
            info.ok = true;
        }
    }

    // ---- images, samplers, textures, materials ----
    void check_images() {
        for (auto [i, im] : items("images")) {
            const std::string p = at("images", i);
            Soft soft(*this);  // an unusable image gets the loader's fallback texture and a warning
            const bool has_uri = get(*im, "uri"), has_view = get(*im, "bufferView");
            if (has_uri == has_view) problem(p, "must have exactly one of 'uri' and 'bufferView'");
            const std::string* mime = string(*im, "mimeType", p, false);
            const std::string* uri = string(*im, "uri", p, false);
            if (has_view) {
                int64_t view;
                --soft_;  // a dangling bufferView is an error like any other reference
                view = ref(*im, "bufferView", p, "bufferViews", false);
                ++soft_;
                if (!mime) problem(p, "an image in a bufferView needs a mimeType");
                if (view >= 0 && views_[static_cast<size_t>(view)].stride)
                    problem(at(p, "bufferView"), "bufferView " + std::to_string(view) + " of an image cannot have a byteStride");
                if (view >= 0 && views_[static_cast<size_t>(view)].unavailable)
                    warn(at(p, "bufferView"), "bufferView " + std::to_string(view) + " lies in a buffer whose data is not available");
            }
            std::string type = mime ? *mime : "";
            if (uri) {
                if (auto data = parse_data_uri(*uri)) {
                    size_t decoded = 0;
                    if (!data->base64 || !valid_base64(data->payload, &decoded)) problem(at(p, "uri"), "is not a valid base64 data URI");
                    else if (!starts_with(data->media_type, "image/"))
                        problem(at(p, "uri"), "data URI media type '" + data->media_type + "' is not an image type");
                    type = data->media_type;
                } else if (const std::string why = uri_problem(*uri); !why.empty()) {
                    problem(at(p, "uri"), why);
                }
            }
            if (!type.empty()) {
                const bool core = type == "image/png" || type == "image/jpeg";
                const bool by_ext = (type == "image/webp" && used("EXT_texture_webp")) || (type == "image/ktx2" && used("KHR_texture_basisu")) ||
                                    (type == "image/avif" && used("EXT_texture_avif"));
                if (!core && !by_ext) problem(mime ? at(p, "mimeType") : at(p, "uri"), "media type '" + type + "' is not image/png or image/jpeg");
            }
            image_type_.push_back(type);
        }
    }

    void check_samplers() {
        for (const auto& [index, sampler] : items("samplers")) {
            const json* s = sampler;  // a lambda cannot capture a structured binding before C++20's clang 16
            const std::string p = at("samplers", index);
            auto in = [&](const char* key, std::initializer_list<int64_t> values) {
                const auto v = integer(*s, key, p, false, 0);
                if (v && std::find(values.begin(), values.end(), *v) == values.end())
                    warn(at(p, key), std::to_string(*v) + " is not a valid value; the default is used");
            };
            in("magFilter", {9728, 9729});
            in("minFilter", {9728, 9729, 9984, 9985, 9986, 9987});
            in("wrapS", {33071, 33648, 10497});
            in("wrapT", {33071, 33648, 10497});
        }
    }

    void check_textures() {
        static const char* source_exts[] = {"EXT_texture_webp", "KHR_texture_basisu", "EXT_texture_avif", "MSFT_texture_dds"};
        for (auto [i, t] : items("textures")) {
            const std::string p = at("textures", i);
            ref(*t, "sampler", p, "samplers", false);
            const int64_t source = ref(*t, "source", p, "images", false);
            if (source >= 0 && static_cast<size_t>(source) < image_type_.size()) {
                const std::string& type = image_type_[static_cast<size_t>(source)];
                if (!type.empty() && type != "image/png" && type != "image/jpeg")
                    warn(at(p, "source"), "image " + std::to_string(source) + " is '" + type +
                                              "', which a texture's source cannot be (only PNG or JPEG); the fallback texture is used");
            }
            if (const json* ext = get(*t, "extensions"))
                for (const char* e : source_exts)
                    if (const json* o = get(*ext, e)) {
                        Soft soft(*this);
                        ref(*o, "source", at(at(p, "extensions"), e), "images", true, "image");
                    }
        }
    }

    // A textureInfo (baseColorTexture, normalTexture, ..., and those of material extensions).
    void check_texture_info(const json& ti, const std::string& p) {
        if (!ti.is_object()) return problem(p, "must be an object");
        ref(ti, "index", p, "textures", true, "texture");
        integer(ti, "texCoord", p, false, 0);
        if (const auto s = number(ti, "strength", p, false); s && (*s < 0 || *s > 1))
            warn(at(p, "strength"), num(*s) + " is outside [0, 1]");
        number(ti, "scale", p, false);
        if (const json* e = get(ti, "extensions"))
            if (const json* tt = get(*e, "KHR_texture_transform"); tt && tt->is_object()) {
                const std::string tp = at(at(p, "extensions"), "KHR_texture_transform");
                numbers(*tt, "offset", tp, 2);
                numbers(*tt, "scale", tp, 2);
                number(*tt, "rotation", tp, false);
                integer(*tt, "texCoord", tp, false, 0);
            }
    }

    void check_materials() {
        for (auto [i, m] : items("materials")) {
            const std::string p = at("materials", i);
            walk(*m, p, "material", [&](const json& obj, const std::string& path, const std::string& kind) {
                if (kind == "textureInfo") {
                    std::optional<Soft> soft;
                    if (path.find(".extensions.") != std::string::npos) {
                        const size_t s = path.find(".extensions.") + 12;
                        if (!extension_implemented(path.substr(s, path.find('.', s) - s))) soft.emplace(*this);
                    }
                    check_texture_info(obj, path);
                }
            });
            if (const json* pbr = get(*m, "pbrMetallicRoughness"); pbr && !pbr->is_object())
                problem(at(p, "pbrMetallicRoughness"), "must be an object");
            else if (pbr) {
                const std::string pp = at(p, "pbrMetallicRoughness");
                numbers(*pbr, "baseColorFactor", pp, 4);
                number(*pbr, "metallicFactor", pp, false);
                number(*pbr, "roughnessFactor", pp, false);
            }
            numbers(*m, "emissiveFactor", p, 3);
            string(*m, "alphaMode", p, false);
            number(*m, "alphaCutoff", p, false);
            if (const json* ds = get(*m, "doubleSided"); ds && !ds->is_boolean()) problem(at(p, "doubleSided"), "must be true or false");
        }
    }

    // ---- cameras and lights ----
    void check_cameras() {
        for (auto [i, c] : items("cameras")) {
            const std::string p = at("cameras", i);
            const std::string* type = string(*c, "type", p, true);
            if (!type) continue;
            if (*type != "perspective" && *type != "orthographic") {
                problem(at(p, "type"), "'" + *type + "' is neither perspective nor orthographic");
                continue;
            }
            const char* other = *type == "perspective" ? "orthographic" : "perspective";
            if (get(*c, other)) problem(p, "has a '" + std::string(other) + "' object but its type is " + *type);
            const json* o = get(*c, type->c_str());
            const std::string op = at(p, *type);
            if (!o || !o->is_object()) {
                problem(p, "needs a '" + *type + "' object");
                continue;
            }
            if (*type == "perspective") {
                const auto yfov = number(*o, "yfov", op, true);
                const auto znear = number(*o, "znear", op, true);
                const auto zfar = number(*o, "zfar", op, false);
                const auto aspect = number(*o, "aspectRatio", op, false);
                if (yfov && !(*yfov > 0)) problem(at(op, "yfov"), num(*yfov) + " must be positive");
                else if (yfov && *yfov >= kPi) warn(at(op, "yfov"), num(*yfov) + " should be less than pi");
                if (znear && !(*znear > 0)) problem(at(op, "znear"), num(*znear) + " must be positive");
                if (zfar && !(*zfar > 0)) problem(at(op, "zfar"), num(*zfar) + " must be positive");
                else if (zfar && znear && *zfar <= *znear) problem(op, "zfar " + num(*zfar) + " must be greater than znear " + num(*znear));
                if (aspect && !(*aspect > 0)) problem(at(op, "aspectRatio"), num(*aspect) + " must be positive");
            } else {
                const auto xmag = number(*o, "xmag", op, true);
                const auto ymag = number(*o, "ymag", op, true);
                const auto znear = number(*o, "znear", op, true);
                const auto zfar = number(*o, "zfar", op, true);
                for (auto [key, v] : {std::pair{"xmag", xmag}, std::pair{"ymag", ymag}}) {
                    if (v && *v == 0) problem(at(op, key), "must not be zero");
                    else if (v && *v < 0) warn(at(op, key), num(*v) + " should not be negative");
                }
                if (znear && *znear < 0) problem(at(op, "znear"), num(*znear) + " must not be negative");
                if (zfar && !(*zfar > 0)) problem(at(op, "zfar"), num(*zfar) + " must be positive");
                else if (zfar && znear && *zfar <= *znear) problem(op, "zfar " + num(*zfar) + " must be greater than znear " + num(*znear));
            }
        }
    }

    // KHR_lights_punctual (its spec and schema): lights at the top level, nodes refer to them.
    void check_lights() {
        const json* ext = get(d_, "extensions");
        const json* lp = ext ? get(*ext, "KHR_lights_punctual") : nullptr;
        const std::string p = "extensions.KHR_lights_punctual";
        if (lp && lp->is_object()) {
            const json* lights = get(*lp, "lights");
            if (!lights || !lights->is_array() || lights->empty()) problem(p, "needs a non-empty 'lights' array");
            else
                for (size_t i = 0; i < lights->size(); ++i) {
                    const json& l = (*lights)[i];
                    const std::string lpath = at(at(p, "lights"), i);
                    if (!l.is_object()) {
                        problem(lpath, "must be an object");
                        continue;
                    }
                    ++light_count_;
                    const std::string* type = string(l, "type", lpath, true);
                    if (type && *type != "directional" && *type != "point" && *type != "spot")
                        warn(at(lpath, "type"), "'" + *type + "' is not directional, point or spot; the light is ignored");
                    numbers(l, "color", lpath, 3);
                    number(l, "intensity", lpath, false);
                    if (const auto r = number(l, "range", lpath, false); r && !(*r > 0)) problem(at(lpath, "range"), num(*r) + " must be positive");
                    const json* spot = get(l, "spot");
                    if (type && *type == "spot" && (!spot || !spot->is_object())) {
                        problem(lpath, "a spot light needs a 'spot' object");
                    } else if (spot && spot->is_object()) {
                        const std::string sp = at(lpath, "spot");
                        const double inner = number(*spot, "innerConeAngle", sp, false).value_or(0.0);
                        const double outer = number(*spot, "outerConeAngle", sp, false).value_or(kPi / 4);
                        if (inner < 0 || inner >= kPi / 2) problem(at(sp, "innerConeAngle"), num(inner) + " is outside [0, pi/2)");
                        if (outer <= 0 || outer > kPi / 2) problem(at(sp, "outerConeAngle"), num(outer) + " is outside (0, pi/2]");
                        else if (outer <= inner)
                            warn(at(sp, "outerConeAngle"), num(outer) + " is not greater than innerConeAngle " + num(inner) + "; clamped");
                    }
                }
        }
        for (auto [i, n] : items("nodes")) {
            const json* ne = get(*n, "extensions");
            const json* nl = ne ? get(*ne, "KHR_lights_punctual") : nullptr;
            if (!nl || !nl->is_object()) continue;
            const std::string np = at(at(at("nodes", i), "extensions"), "KHR_lights_punctual");
            if (const json* l = get(*nl, "light")) ref_value(*l, at(np, "light"), "light", light_count_);
            else problem(np, "'light' is required");
        }
    }

    // An accessor Candela reads must have a known format and data it can get.
    bool unusable(int64_t a, const std::string& path) {
        AccessorInfo& info = accessors_[static_cast<size_t>(a)];
        if (!info.out_of_bounds.empty()) {
            problem(path + " (accessors[" + std::to_string(a) + "])", info.out_of_bounds);
            info.reported = true;
            return true;
        }
        if (info.unknown_format) problem(path, "accessor " + std::to_string(a) + " has an unknown type or componentType");
        else if (info.unavailable) warn(path, "accessor " + std::to_string(a) + " lies in a buffer whose data is not available; not drawn");
        else return false;
        return true;
    }

    // ---- meshes ----
    // Formats from the spec's table of mesh attributes (3.7.2.1), widened by KHR_mesh_quantization.
    std::string attribute_format_problem(const std::string& name, const AccessorInfo& a) const {
        const bool q = used("KHR_mesh_quantization");
        const int64_t ct = a.component_type;
        const bool f = ct == kFloat;
        const bool unorm8_16 = (ct == kUByte || ct == kUShort) && a.normalized;
        const bool any_8_16 = ct == kByte || ct == kUByte || ct == kShort || ct == kUShort;
        const bool snorm8_16 = (ct == kByte || ct == kShort) && a.normalized;
        auto fmt = [&](bool ok, const char* types, const char* comps) -> std::string {
            return ok ? std::string() : std::string("must be ") + types + " " + comps;
        };
        if (name == "POSITION") return fmt(a.type == "VEC3" && (f || (q && any_8_16)), q ? "FLOAT or (normalized) 8/16-bit" : "FLOAT", "VEC3");
        if (name == "NORMAL") return fmt(a.type == "VEC3" && (f || (q && snorm8_16)), "FLOAT", "VEC3");
        if (name == "TANGENT") return fmt(a.type == "VEC4" && (f || (q && snorm8_16)), "FLOAT", "VEC4");
        if (set_index(name, "TEXCOORD_") >= 0)
            return fmt(a.type == "VEC2" && (f || unorm8_16 || (q && any_8_16)), "FLOAT or normalized UNSIGNED_BYTE/SHORT", "VEC2");
        if (set_index(name, "COLOR_") >= 0)
            return fmt((a.type == "VEC3" || a.type == "VEC4") && (f || unorm8_16), "FLOAT or normalized UNSIGNED_BYTE/SHORT", "VEC3/VEC4");
        if (set_index(name, "JOINTS_") >= 0)
            return fmt(a.type == "VEC4" && (ct == kUByte || ct == kUShort) && !a.normalized, "UNSIGNED_BYTE/SHORT", "VEC4");
        if (set_index(name, "WEIGHTS_") >= 0)
            return fmt(a.type == "VEC4" && (f || unorm8_16), "FLOAT or normalized UNSIGNED_BYTE/SHORT", "VEC4");
        if (!name.empty() && name[0] == '_' && ct == kUInt) return "a custom attribute cannot be UNSIGNED_INT";
        return {};
    }
    static bool known_semantic(const std::string& name) {
        if (name == "POSITION" || name == "NORMAL" || name == "TANGENT") return true;
        for (const char* p : {"TEXCOORD_", "COLOR_", "JOINTS_", "WEIGHTS_"})
            if (set_index(name, p) >= 0) return true;
        return !name.empty() && name[0] == '_';
    }
    // Attributes Candela reads; the others (TEXCOORD_2+, COLOR_1+, custom) it ignores.
    static bool read_by_candela(const std::string& name) {
        return name == "POSITION" || name == "NORMAL" || name == "TANGENT" || name == "TEXCOORD_0" || name == "TEXCOORD_1" ||
               name == "COLOR_0" || set_index(name, "JOINTS_") >= 0 || set_index(name, "WEIGHTS_") >= 0;
    }

    // texCoord sets and normal maps a material asks of a primitive.
    struct MaterialNeeds {
        std::vector<std::pair<int64_t, std::string>> texcoords;  // (set, JSON path of the textureInfo)
        std::string normal_map;                                  // path of a normal texture, if any
    };
    MaterialNeeds material_needs(int64_t m) const {
        MaterialNeeds needs;
        const json* mat = item("materials", m);
        if (!mat) return needs;
        walk(*mat, at("materials", static_cast<size_t>(m)), "material", [&](const json& obj, const std::string& path, const std::string& kind) {
            if (kind != "textureInfo" || !obj.is_object()) return;
            int64_t set = 0;
            if (const json* tc = get(obj, "texCoord"); tc && tc->is_number_integer()) set = tc->get<int64_t>();
            if (const json* e = get(obj, "extensions"))
                if (const json* tt = get(*e, "KHR_texture_transform"))
                    if (const json* tc = get(*tt, "texCoord"); tc && tc->is_number_integer()) set = tc->get<int64_t>();
            needs.texcoords.emplace_back(set, path);
            if (ends_with(path, "ormalTexture") && needs.normal_map.empty()) needs.normal_map = path;
        });
        // Anisotropy is defined in the tangent space (KHR_materials_anisotropy), with or without a texture.
        if (const json* e = get(*mat, "extensions"); e && get(*e, "KHR_materials_anisotropy") && needs.normal_map.empty())
            needs.normal_map = at(at(at("materials", static_cast<size_t>(m)), "extensions"), "KHR_materials_anisotropy");
        return needs;
    }

    void check_meshes() {
        morph_targets_.assign(count("meshes"), 0);
        for (auto [mi, m] : items("meshes")) {
            const std::string p = at("meshes", mi);
            const json* prims = get(*m, "primitives");
            if (!prims || !prims->is_array() || prims->empty()) {
                problem(p, "needs a non-empty 'primitives' array");
                continue;
            }
            std::optional<size_t> targets;
            for (size_t pi = 0; pi < prims->size(); ++pi) {
                const json& prim = (*prims)[pi];
                const std::string pp = at(at(p, "primitives"), pi);
                if (!prim.is_object()) {
                    problem(pp, "must be an object");
                    continue;
                }
                const size_t t = check_primitive(prim, pp);
                if (!targets) targets = t;
                else if (*targets != t)
                    error(at(pp, "targets"), "has " + std::to_string(t) + " morph targets, primitive 0 has " + std::to_string(*targets));
            }
            morph_targets_[mi] = targets.value_or(0);
            if (const json* w = numbers(*m, "weights", p, 0); w && w->size() != morph_targets_[mi])
                error(at(p, "weights"), "has " + std::to_string(w->size()) + " weights for " + std::to_string(morph_targets_[mi]) + " morph targets");
        }
    }

    // Returns the number of morph targets.
    size_t check_primitive(const json& prim, const std::string& pp) {
        const json* attrs = get(prim, "attributes");
        if (!attrs || !attrs->is_object() || attrs->empty()) {
            problem(pp, "needs a non-empty 'attributes' object");
            return 0;
        }
        const std::string ap = at(pp, "attributes");
        std::map<std::string, int64_t> base;  // attribute -> accessor
        int64_t vertex_count = -1;
        std::string count_from;
        std::map<int64_t, int> view_users;
        for (auto it = attrs->begin(); it != attrs->end(); ++it) {
            const std::string& name = it.key();
            const std::string p = at(ap, name);
            std::optional<Soft> soft;
            if (!read_by_candela(name)) soft.emplace(*this);
            if (!known_semantic(name)) {
                warn(p, "'" + name + "' is not a glTF attribute semantic; ignored");
                continue;
            }
            const int64_t a = ref_value(*it, p, "accessor", count("accessors"));
            if (a < 0) continue;
            base[name] = a;
            const AccessorInfo& info = accessors_[static_cast<size_t>(a)];
            if (unusable(a, p) || !info.ok) continue;
            if (const std::string why = attribute_format_problem(name, info); !why.empty())
                problem(p, "accessor " + std::to_string(a) + " is " + component_name(info.component_type) + (info.normalized ? " normalized " : " ") +
                               info.type + "; " + name + " " + why);
            if (name == "POSITION" && (!info.has_min || !info.has_max))
                warn(p, "accessor " + std::to_string(a) + " has no min and max (required for POSITION)");
            if (info.view >= 0) {
                const ViewInfo& v = views_[static_cast<size_t>(info.view)];
                ++view_users[info.view];
                if ((info.offset % 4 != 0 || (v.offset + info.offset) % 4 != 0))
                    warn(p, "accessor " + std::to_string(a) + " does not start on a 4-byte boundary");
                if (v.target == kElementArrayBuffer)
                    warn(p, "accessor " + std::to_string(a) + "'s bufferView " + std::to_string(info.view) + " is an index buffer (target 34963)");
            }
            if (vertex_count < 0) {
                vertex_count = info.count;
                count_from = name;
            } else if (info.count != vertex_count) {
                problem(p, "accessor " + std::to_string(a) + " has " + std::to_string(info.count) + " elements, " + count_from + " has " +
                               std::to_string(vertex_count));
            }
        }
        for (auto [view, users] : view_users)
            if (users > 1 && views_[static_cast<size_t>(view)].ok && views_[static_cast<size_t>(view)].stride == 0)
                warn(ap, std::to_string(users) + " attributes share bufferView " + std::to_string(view) + ", which has no byteStride");
        for (const char* prefix : {"TEXCOORD_", "COLOR_", "JOINTS_", "WEIGHTS_"}) {
            std::set<int> sets;
            for (const auto& [name, a] : base)
                if (const int s = set_index(name, prefix); s >= 0) sets.insert(s);
            if (!sets.empty() && *sets.rbegin() + 1 != static_cast<int>(sets.size()))
                warn(ap, std::string(prefix) + "n sets are not numbered 0, 1, 2... without gaps");
        }
        for (const auto& [name, a] : base) {
            const int j = set_index(name, "JOINTS_");
            if (j >= 0 && !base.count("WEIGHTS_" + std::to_string(j))) problem(ap, name + " has no matching WEIGHTS_" + std::to_string(j));
            const int w = set_index(name, "WEIGHTS_");
            if (w >= 0 && !base.count("JOINTS_" + std::to_string(w))) problem(ap, name + " has no matching JOINTS_" + std::to_string(w));
        }
        if (get(prim, "indices")) {
            const int64_t a = ref(prim, "indices", pp, "accessors", false, "accessor");
            if (a >= 0 && !unusable(a, at(pp, "indices")) && accessors_[static_cast<size_t>(a)].ok) {
                const AccessorInfo& info = accessors_[static_cast<size_t>(a)];
                const int64_t ct = info.component_type;
                if (info.type != "SCALAR" || info.normalized || (ct != kUByte && ct != kUShort && ct != kUInt))
                    problem(at(pp, "indices"), "accessor " + std::to_string(a) + " is " + component_name(ct) + " " + info.type +
                                                   "; indices must be SCALAR UNSIGNED_BYTE, _SHORT or _INT, not normalized");
                if (info.view >= 0) {
                    const ViewInfo& v = views_[static_cast<size_t>(info.view)];
                    if (v.stride) problem(at(pp, "indices"), "bufferView " + std::to_string(info.view) + " of indices cannot have a byteStride");
                    if (v.target == kArrayBuffer)
                        warn(at(pp, "indices"), "bufferView " + std::to_string(info.view) + " is a vertex buffer (target 34962)");
                }
            }
        }
        integer(prim, "mode", pp, false, 0, 6);
        const int64_t material = ref(prim, "material", pp, "materials", false);
        if (material >= 0) {
            const MaterialNeeds needs = material_needs(material);
            for (const auto& [set, path] : needs.texcoords)
                if (!base.count("TEXCOORD_" + std::to_string(set))) {
                    warn(at(pp, "material"), path + " uses TEXCOORD_" + std::to_string(set) + ", which the primitive does not have");
                    break;
                }
            if (!needs.normal_map.empty() && !base.count("NORMAL"))
                warn(at(pp, "material"), needs.normal_map + " needs a tangent space but the primitive has no NORMAL (flat normals are generated)");
        }
        // Morph targets: what the loader reads (POSITION, NORMAL, TANGENT deltas, one per vertex) is
        // checked as errors; the rest (semantics it cannot morph, a delta without a base attribute) warns.
        Soft soft(*this);
        const json* targets = get(prim, "targets");
        if (!targets) return 0;
        const std::string tp = at(pp, "targets");
        if (!targets->is_array()) {
            problem(tp, "must be an array");
            return 0;
        }
        if (targets->empty()) warn(tp, "is an empty array (omit it instead)");
        for (size_t ti = 0; ti < targets->size(); ++ti) {
            const json& t = (*targets)[ti];
            const std::string p = at(tp, ti);
            if (!t.is_object() || t.empty()) {
                problem(p, "must be a non-empty object");
                continue;
            }
            for (auto it = t.begin(); it != t.end(); ++it) {
                const std::string& name = it.key();
                const std::string ip = at(p, name);
                if (!known_semantic(name) || set_index(name, "JOINTS_") >= 0 || set_index(name, "WEIGHTS_") >= 0) {
                    problem(ip, "'" + name + "' cannot be morphed");
                    continue;
                }
                const int64_t a = ref_value(*it, ip, "accessor", count("accessors"));
                if (a < 0) continue;
                if (!base.count(name)) problem(ip, "the primitive has no base " + name + " attribute");
                const AccessorInfo& info = accessors_[static_cast<size_t>(a)];
                if (!info.ok) continue;
                if (vertex_count >= 0 && info.count != vertex_count)
                    error(ip, "accessor " + std::to_string(a) + " has " + std::to_string(info.count) + " elements, the primitive has " +
                                  std::to_string(vertex_count) + " vertices");
                if (name == "POSITION" && (!info.has_min || !info.has_max)) problem(ip, "accessor " + std::to_string(a) + " has no min and max");
                if (info.view >= 0 && views_[static_cast<size_t>(info.view)].target == kElementArrayBuffer)
                    problem(ip, "accessor " + std::to_string(a) + "'s bufferView is an index buffer (target 34963)");
                if ((name == "POSITION" || name == "NORMAL" || name == "TANGENT") && info.type != "VEC3")
                    error(ip, "accessor " + std::to_string(a) + " must be VEC3, not " + info.type);
            }
        }
        return targets->size();
    }

    // ---- nodes, scenes, skins ----
    void check_nodes() {
        const size_t n = count("nodes");
        parent_.assign(n, -1);
        for (auto [i, node] : items("nodes")) {
            const std::string p = at("nodes", i);
            ref(*node, "camera", p, "cameras", false);
            const int64_t mesh = ref(*node, "mesh", p, "meshes", false);
            {
                const int64_t skin = ref(*node, "skin", p, "skins", false);
                Soft soft(*this);
                if (get(*node, "skin") && !get(*node, "mesh")) problem(at(p, "skin"), "a skin needs a mesh on the same node");
                if (skin >= 0 && mesh >= 0) {
                    bool skinned = false;
                    const json* m = item("meshes", mesh);
                    if (const json* prims = m ? get(*m, "primitives") : nullptr; prims && prims->is_array())
                        for (const auto& pr : *prims)
                            if (const json* at = get(pr, "attributes"); at && at->is_object() && at->contains("JOINTS_0") && at->contains("WEIGHTS_0"))
                                skinned = true;
                    if (!skinned) problem(at(p, "skin"), "mesh " + std::to_string(mesh) + " has no JOINTS_0 and WEIGHTS_0 to skin");
                }
                if (const json* w = numbers(*node, "weights", p, 0)) {
                    if (mesh < 0) problem(at(p, "weights"), "morph weights need a mesh on the same node");
                    else if (static_cast<size_t>(mesh) < morph_targets_.size() && w->size() != morph_targets_[static_cast<size_t>(mesh)])
                        error(at(p, "weights"), "has " + std::to_string(w->size()) + " weights, mesh " + std::to_string(mesh) + " has " +
                                                      std::to_string(morph_targets_[static_cast<size_t>(mesh)]) + " morph targets");
                }
            }
            const json* matrix = numbers(*node, "matrix", p, 16);
            if (matrix) {
                const json& mm = *matrix;
                if (mm[3].get<double>() != 0 || mm[7].get<double>() != 0 || mm[11].get<double>() != 0 || mm[15].get<double>() != 1)
                    problem(at(p, "matrix"), "is not an affine transform (its last row must be 0 0 0 1), so it is not a TRS");
                if (get(*node, "translation") || get(*node, "rotation") || get(*node, "scale"))
                    warn(p, "has both a matrix and translation/rotation/scale; the matrix is used");
            }
            numbers(*node, "translation", p, 3);
            numbers(*node, "scale", p, 3);
            if (const json* r = numbers(*node, "rotation", p, 4)) {
                // A component outside [-1, 1] (the schema's range) makes the length exceed 1, so it
                // is this warning too; float rounding of a unit quaternion (1.0000001) stays silent.
                double len2 = 0;
                for (const auto& c : *r) len2 += c.get<double>() * c.get<double>();
                if (std::fabs(std::sqrt(len2) - 1.0) > 1e-4)
                    warn(at(p, "rotation"), "is not a unit quaternion (length " + num(std::sqrt(len2)) + "); normalised");
            }
            for (int64_t c : ref_array(*node, "children", p, "nodes", "node", false)) {
                const std::string cp = at(p, "children");
                if (static_cast<size_t>(c) == i) problem(cp, "node " + std::to_string(c) + " is its own child");
                else if (parent_[static_cast<size_t>(c)] >= 0)
                    problem(cp, "node " + std::to_string(c) + " already has parent " + std::to_string(parent_[static_cast<size_t>(c)]) +
                                    " (the hierarchy must be a tree)");
                else parent_[static_cast<size_t>(c)] = static_cast<int64_t>(i);
            }
        }
    }

    // A loop: following parents from a node comes back to it. After check_scenes, whose message
    // (a root that is also a child) is the clearer one when a scene lists a node of the loop.
    void check_node_loops() {
        const size_t n = parent_.size();
        for (size_t i = 0; i < n; ++i) {
            int64_t k = parent_[i];
            for (size_t steps = 0; k >= 0 && steps <= n; ++steps) {
                if (static_cast<size_t>(k) == i) {
                    problem(at("nodes", i), "is its own ancestor (the children form a loop)");
                    return;
                }
                k = parent_[static_cast<size_t>(k)];
            }
        }
    }

    void check_scenes() {
        for (auto [i, s] : items("scenes")) {
            const std::string p = at("scenes", i);
            for (int64_t r : ref_array(*s, "nodes", p, "nodes", "node", false))
                if (parent_[static_cast<size_t>(r)] >= 0)
                    problem(at(p, "nodes"), "node " + std::to_string(r) + " is a root and also a child (of node " +
                                                std::to_string(parent_[static_cast<size_t>(r)]) + ")");
        }
    }

    // A skinned node drawn by a scene needs its joints in that scene too (spec 3.7.3).
    void check_skinned_nodes_in_scenes() {
        for (auto [si, s] : items("scenes")) {
            const json* roots = get(*s, "nodes");
            if (!roots || !roots->is_array()) continue;
            std::set<int64_t> in_scene;
            for (const auto& r : *roots)
                if (r.is_number_integer() && r.get<int64_t>() >= 0 && static_cast<size_t>(r.get<int64_t>()) < parent_.size())
                    in_scene.insert(r.get<int64_t>());
            for (size_t i = 0; i < parent_.size(); ++i)  // add descendants: a node is in if its root is
                if (in_scene.count(root_of(static_cast<int64_t>(i)))) in_scene.insert(static_cast<int64_t>(i));
            for (int64_t n : in_scene) {
                const json* node = item("nodes", n);
                const json* skin_ref = node ? get(*node, "skin") : nullptr;
                if (!skin_ref || !skin_ref->is_number_integer()) continue;
                const json* skin = item("skins", skin_ref->get<int64_t>());
                const json* joints = skin ? get(*skin, "joints") : nullptr;
                if (!joints || !joints->is_array()) continue;
                for (const auto& j : *joints)
                    if (j.is_number_integer() && !in_scene.count(j.get<int64_t>())) {
                        problem(at("nodes", static_cast<size_t>(n)), "is skinned in scene " + std::to_string(si) + ", which does not contain its joint " +
                                                                      std::to_string(j.get<int64_t>()));
                        break;
                    }
            }
        }
    }

    int64_t root_of(int64_t n) const {
        for (size_t steps = 0; parent_[static_cast<size_t>(n)] >= 0 && steps < parent_.size(); ++steps) n = parent_[static_cast<size_t>(n)];
        return n;
    }
    bool is_ancestor_or_self(int64_t a, int64_t n) const {
        for (size_t steps = 0; n >= 0 && steps <= parent_.size(); ++steps, n = parent_[static_cast<size_t>(n)])
            if (n == a) return true;
        return false;
    }

    void check_skins() {
        for (auto [i, s] : items("skins")) {
            const std::string p = at("skins", i);
            const std::vector<int64_t> joints = ref_array(*s, "joints", p, "nodes", "node", true);
            const int64_t ibm = ref(*s, "inverseBindMatrices", p, "accessors", false, "accessor");
            if (ibm >= 0 && accessors_[static_cast<size_t>(ibm)].ok) {
                const AccessorInfo& a = accessors_[static_cast<size_t>(ibm)];
                if (a.type != "MAT4" || a.component_type != kFloat)
                    problem(at(p, "inverseBindMatrices"), "accessor " + std::to_string(ibm) + " must be FLOAT MAT4");
                if (a.count < static_cast<int64_t>(joints.size()))
                    problem(at(p, "inverseBindMatrices"), "accessor " + std::to_string(ibm) + " has " + std::to_string(a.count) +
                                                              " matrices for " + std::to_string(joints.size()) + " joints");
                if (a.view >= 0 && views_[static_cast<size_t>(a.view)].stride)
                    warn(at(p, "inverseBindMatrices"), "bufferView " + std::to_string(a.view) + " cannot have a byteStride");
            }
            Soft soft(*this);  // informative for posing (which uses the joints' world matrices)
            const int64_t skeleton = ref(*s, "skeleton", p, "nodes", false, "node");
            if (get(*s, "joints") && joints.empty()) continue;
            bool common = true;
            for (int64_t j : joints) common = common && root_of(j) == root_of(joints[0]);
            if (!common) problem(at(p, "joints"), "the joints do not have a common root");
            if (skeleton >= 0)
                for (int64_t j : joints)
                    if (!is_ancestor_or_self(skeleton, j)) {
                        problem(at(p, "skeleton"), "node " + std::to_string(skeleton) + " is not an ancestor of joint " + std::to_string(j));
                        break;
                    }
        }
    }

    // Errors: what sampling reads (input times as FLOAT SCALAR, an output whose format fits the
    // path and whose count fits the input); the rest warns and the loader drops what it cannot use.
    void check_animations() {
        static const std::set<std::string> paths = {"translation", "rotation", "scale", "weights"};
        Soft soft(*this);
        for (auto [i, anim] : items("animations")) {
            const std::string p = at("animations", i);
            const json* samplers = get(*anim, "samplers");
            const json* channels = get(*anim, "channels");
            if (!samplers || !samplers->is_array() || samplers->empty()) problem(p, "needs a non-empty 'samplers' array");
            if (!channels || !channels->is_array() || channels->empty()) problem(p, "needs a non-empty 'channels' array");
            const size_t ns = samplers && samplers->is_array() ? samplers->size() : 0;
            std::vector<std::pair<int64_t, int64_t>> io(ns, {-1, -1});
            std::vector<std::string> interp(ns, "LINEAR");
            for (size_t si = 0; si < ns; ++si) {
                const json& s = (*samplers)[si];
                const std::string sp = at(at(p, "samplers"), si);
                if (!s.is_object()) {
                    problem(sp, "must be an object");
                    continue;
                }
                io[si].first = ref(s, "input", sp, "accessors", true, "accessor");
                io[si].second = ref(s, "output", sp, "accessors", true, "accessor");
                if (const std::string* m = string(s, "interpolation", sp, false)) {
                    if (*m != "LINEAR" && *m != "STEP" && *m != "CUBICSPLINE")
                        problem(at(sp, "interpolation"), "'" + *m + "' is not LINEAR, STEP or CUBICSPLINE");
                    else interp[si] = *m;
                }
                for (auto [key, a] : {std::pair{"input", io[si].first}, std::pair{"output", io[si].second}}) {
                    if (a < 0 || !accessors_[static_cast<size_t>(a)].ok) continue;
                    const AccessorInfo& info = accessors_[static_cast<size_t>(a)];
                    if (info.view >= 0 && views_[static_cast<size_t>(info.view)].stride)
                        problem(at(sp, key), "bufferView " + std::to_string(info.view) + " of animation data cannot have a byteStride");
                }
                if (io[si].first >= 0 && accessors_[static_cast<size_t>(io[si].first)].ok) {
                    const AccessorInfo& in = accessors_[static_cast<size_t>(io[si].first)];
                    if (in.type != "SCALAR" || in.component_type != kFloat)
                        error(at(sp, "input"), "accessor " + std::to_string(io[si].first) + " must be FLOAT SCALAR (times in seconds)");
                    if (!in.has_min || !in.has_max) problem(at(sp, "input"), "accessor " + std::to_string(io[si].first) + " needs min and max");
                    if (interp[si] == "CUBICSPLINE" && in.count < 2)
                        problem(at(sp, "input"), "CUBICSPLINE needs at least 2 keyframes, accessor has " + std::to_string(in.count));
                }
            }
            if (!channels || !channels->is_array()) continue;
            std::set<std::pair<int64_t, std::string>> targets;
            for (size_t ci = 0; ci < channels->size(); ++ci) {
                const json& c = (*channels)[ci];
                const std::string cp = at(at(p, "channels"), ci);
                if (!c.is_object()) {
                    problem(cp, "must be an object");
                    continue;
                }
                const json* sv = get(c, "sampler");
                const int64_t s = sv ? ref_value(*sv, at(cp, "sampler"), "sampler", ns) : -1;
                if (!sv) problem(cp, "'sampler' is required");
                const json* t = get(c, "target");
                if (!t || !t->is_object()) {
                    problem(cp, "needs a 'target' object");
                    continue;
                }
                const std::string tp = at(cp, "target");
                const json* te = get(*t, "extensions");
                const json* pointer = te ? get(*te, "KHR_animation_pointer") : nullptr;
                const std::string* path = string(*t, "path", tp, true);
                if (pointer && pointer->is_object()) {
                    const std::string pp = at(at(tp, "extensions"), "KHR_animation_pointer");
                    const std::string* ptr = string(*pointer, "pointer", pp, true);
                    if (ptr && (ptr->empty() || (*ptr)[0] != '/')) problem(at(pp, "pointer"), "'" + *ptr + "' is not a JSON pointer");
                    if (get(*t, "node")) problem(at(tp, "node"), "must not be set with KHR_animation_pointer");
                    if (path && *path != "pointer") problem(at(tp, "path"), "must be 'pointer' with KHR_animation_pointer, not '" + *path + "'");
                    continue;
                }
                if (path && !paths.count(*path)) {
                    problem(at(tp, "path"), "'" + *path + "' is not translation, rotation, scale or weights");
                    path = nullptr;
                }
                const int64_t node = ref(*t, "node", tp, "nodes", false, "node");
                if (node < 0 || !path) continue;
                if (!targets.insert({node, *path}).second) problem(tp, "node " + std::to_string(node) + " " + *path + " is animated twice");
                const json* nj = item("nodes", node);
                if (nj && get(*nj, "matrix") && *path != "weights")
                    warn(tp, "node " + std::to_string(node) + " has a matrix; TRS animation needs translation/rotation/scale (the channel is ignored)");
                int64_t morphs = 0;
                if (*path == "weights") {
                    const json* mesh = nj ? get(*nj, "mesh") : nullptr;
                    if (mesh && mesh->is_number_integer() && mesh->get<int64_t>() >= 0 &&
                        static_cast<size_t>(mesh->get<int64_t>()) < morph_targets_.size())
                        morphs = static_cast<int64_t>(morph_targets_[static_cast<size_t>(mesh->get<int64_t>())]);
                    if (morphs == 0) problem(tp, "node " + std::to_string(node) + " has no mesh with morph targets to animate");
                }
                if (s < 0 || io[static_cast<size_t>(s)].second < 0) continue;
                const int64_t out = io[static_cast<size_t>(s)].second;
                const AccessorInfo& o = accessors_[static_cast<size_t>(out)];
                if (!o.ok) continue;
                const int64_t ct = o.component_type;
                const bool normalized_ok = o.normalized && ct != kUInt && ct != kFloat;
                bool format_ok = true;
                if (*path == "translation" || *path == "scale") format_ok = o.type == "VEC3" && ct == kFloat;
                else if (*path == "rotation") format_ok = o.type == "VEC4" && (ct == kFloat || normalized_ok);
                else format_ok = o.type == "SCALAR" && (ct == kFloat || normalized_ok);
                if (!format_ok)
                    error(at(cp, "sampler"), "output accessor " + std::to_string(out) + " (" + component_name(ct) + " " + o.type +
                                                   ") does not fit path '" + *path + "'");
                const int64_t in = io[static_cast<size_t>(s)].first;
                if (in >= 0 && accessors_[static_cast<size_t>(in)].ok) {
                    const int64_t expect = accessors_[static_cast<size_t>(in)].count * (interp[static_cast<size_t>(s)] == "CUBICSPLINE" ? 3 : 1) *
                                           (*path == "weights" ? std::max<int64_t>(morphs, 1) : 1);
                    if (o.count != expect && (*path != "weights" || morphs > 0))
                        error(at(cp, "sampler"), "output accessor " + std::to_string(out) + " has " + std::to_string(o.count) + " elements, " +
                                                     std::to_string(expect) + " expected (input accessor " + std::to_string(in) + ": " +
                                                     std::to_string(accessors_[static_cast<size_t>(in)].count) + " keyframes" +
                                                     (interp[static_cast<size_t>(s)] == "CUBICSPLINE" ? " x 3 for CUBICSPLINE" : "") +
                                                     (*path == "weights" ? " x " + std::to_string(morphs) + " morph targets" : "") + ")");
                }
            }
        }
    }

    // KHR_materials_variants (its spec): names at the top level, mappings on primitives.
    void check_variants() {
        const json* ext = get(d_, "extensions");
        const json* v = ext ? get(*ext, "KHR_materials_variants") : nullptr;
        size_t nv = 0;
        if (v && v->is_object()) {
            const std::string p = "extensions.KHR_materials_variants";
            const json* list = get(*v, "variants");
            if (!list || !list->is_array() || list->empty()) problem(p, "needs a non-empty 'variants' array");
            else {
                nv = list->size();
                for (size_t i = 0; i < nv; ++i) {
                    if (!(*list)[i].is_object()) problem(at(at(p, "variants"), i), "must be an object");
                    else string((*list)[i], "name", at(at(p, "variants"), i), true);
                }
            }
        }
        for (auto [mi, m] : items("meshes")) {
            const json* prims = get(*m, "primitives");
            if (!prims || !prims->is_array()) continue;
            for (size_t pi = 0; pi < prims->size(); ++pi) {
                const json* e = get((*prims)[pi], "extensions");
                const json* mv = e ? get(*e, "KHR_materials_variants") : nullptr;
                if (!mv || !mv->is_object()) continue;
                const std::string p = at(at(at(at("meshes", mi), "primitives"), pi), "extensions.KHR_materials_variants");
                const json* maps = get(*mv, "mappings");
                if (!maps || !maps->is_array() || maps->empty()) {
                    problem(p, "needs a non-empty 'mappings' array");
                    continue;
                }
                std::set<int64_t> seen;
                for (size_t k = 0; k < maps->size(); ++k) {
                    const json& map = (*maps)[k];
                    const std::string mp = at(at(p, "mappings"), k);
                    if (!map.is_object()) {
                        problem(mp, "must be an object");
                        continue;
                    }
                    ref(map, "material", mp, "materials", true, "material");
                    const json* vs = get(map, "variants");
                    if (!vs || !vs->is_array() || vs->empty()) {
                        problem(mp, "needs a non-empty 'variants' array");
                        continue;
                    }
                    for (size_t j = 0; j < vs->size(); ++j) {
                        const int64_t r = ref_value((*vs)[j], at(at(mp, "variants"), j), "variant", nv);
                        if (r >= 0 && !seen.insert(r).second) problem(at(at(mp, "variants"), j), "variant " + std::to_string(r) + " is mapped twice");
                    }
                }
            }
        }
    }

    const json& d_;
    bool glb_;
    int64_t bin_;
    int soft_ = 0;
    std::vector<Issue> issues_;
    std::set<std::string> used_;
    std::vector<int64_t> buffer_len_;
    std::set<size_t> unavailable_buffers_;
    std::vector<ViewInfo> views_;
    std::vector<AccessorInfo> accessors_;
    std::vector<std::string> image_type_;
    std::vector<size_t> morph_targets_;
    std::vector<int64_t> parent_;
    size_t light_count_ = 0;
};

// ---- buffer contents ----

class DataChecker {
public:
    DataChecker(const json& doc, const std::vector<std::string_view>& buffers) : d_(doc), buffers_(buffers) {}

    std::vector<Issue> run() {
        try {
            const json* accessors = d_.find("accessors") != d_.end() ? &d_["accessors"] : nullptr;
            if (accessors && accessors->is_array())
                for (size_t i = 0; i < accessors->size(); ++i) check_accessor(i);
            check_mesh_data();
            check_animation_data();
            check_skin_data();
        } catch (const json::exception&) {
            // A member of an unexpected type that the guards above missed (e.g. a numeric
            // "interpolation"): the structure checks name it; these checks only add warnings, so
            // they stop here rather than end the load with an internal error.
        }
        return std::move(issues_);
    }

private:
    void warn(const std::string& path, const std::string& what) { issues_.push_back({false, path, what}); }
    void error(const std::string& path, const std::string& what) { issues_.push_back({true, path, what}); }

    // Components of accessor `i` as doubles (raw values, not normalized), sparse applied; empty
    // when the accessor has no data this checker can read.
    const std::vector<double>& values(size_t i) {
        auto it = cache_.find(i);
        if (it != cache_.end()) return it->second;
        std::vector<double>& out = cache_[i];
        const json& a = d_["accessors"][i];
        const int64_t ct = a.value("componentType", 0);
        const int nc = type_components(a.value("type", std::string()));
        const int64_t n = a.value("count", int64_t(0));
        const int cs = component_size(ct);
        if (!cs || !nc || n <= 0 || n > (int64_t(1) << 26)) return out;
        const std::string type = a.value("type", std::string());
        if (type == "MAT2" || type == "MAT3") {
            if (cs < 4) return out;  // padded columns: not needed for any check here
        }
        out.assign(static_cast<size_t>(n) * static_cast<size_t>(nc), 0.0);
        auto read = [&](const unsigned char* p, int64_t t) -> double {
            switch (t) {
                case kFloat: { float f; std::memcpy(&f, p, 4); return f; }
                case kByte: return static_cast<int8_t>(*p);
                case kUByte: return *p;
                case kShort: { int16_t v; std::memcpy(&v, p, 2); return v; }
                case kUShort: { uint16_t v; std::memcpy(&v, p, 2); return v; }
                case kUInt: { uint32_t v; std::memcpy(&v, p, 4); return v; }
                default: return 0;
            }
        };
        auto view_bytes = [&](const json& holder, int64_t* stride) -> std::string_view {
            if (!holder.is_object()) return {};
            auto vj = holder.find("bufferView");
            auto views = d_.find("bufferViews");
            if (vj == holder.end() || !vj->is_number_integer() || vj->get<int64_t>() < 0 || views == d_.end() || !views->is_array() ||
                vj->get<size_t>() >= views->size() || !(*views)[vj->get<size_t>()].is_object())
                return {};
            const json& v = (*views)[vj->get<size_t>()];
            const size_t b = v.value("buffer", size_t(0));
            if (b >= buffers_.size()) return {};
            const size_t off = v.value("byteOffset", size_t(0)), len = v.value("byteLength", size_t(0));
            if (off > buffers_[b].size() || len > buffers_[b].size() - off) return {};
            *stride = v.value("byteStride", int64_t(0));
            return buffers_[b].substr(off, len);
        };
        if (!a.contains("bufferView") && !a.contains("sparse")) return out = {}, out;  // zeros by definition: nothing to check
        int64_t stride = 0;
        const std::string_view view = view_bytes(a, &stride);
        if (a.contains("bufferView")) {
            if (view.empty()) return out = {}, out;
            const int64_t s = stride ? stride : int64_t(cs) * nc;
            const size_t off = a.value("byteOffset", size_t(0));
            if (off + size_t(s) * size_t(n - 1) + size_t(cs) * size_t(nc) > view.size()) return out = {}, out;
            const auto* base = reinterpret_cast<const unsigned char*>(view.data()) + off;
            for (int64_t e = 0; e < n; ++e)
                for (int c = 0; c < nc; ++c) out[size_t(e) * size_t(nc) + size_t(c)] = read(base + e * s + c * cs, ct);
        }
        if (a.contains("sparse") && a["sparse"].is_object()) {
            const json& s = a["sparse"];
            const int64_t sn = s.value("count", int64_t(0));
            int64_t st = 0;
            if (!s.contains("indices") || !s.contains("values") || !s["indices"].is_object() || !s["values"].is_object()) return out = {}, out;
            const std::string_view iv = view_bytes(s["indices"], &st), vv = view_bytes(s["values"], &st);
            const int64_t ict = s["indices"].value("componentType", 0);
            const int ics = component_size(ict);
            const size_t ioff = s["indices"].value("byteOffset", size_t(0)), voff = s["values"].value("byteOffset", size_t(0));
            if (ics == 0 || ioff + size_t(sn) * size_t(ics) > iv.size() || voff + size_t(sn) * size_t(cs) * size_t(nc) > vv.size())
                return out = {}, out;
            for (int64_t k = 0; k < sn; ++k) {
                const auto target = static_cast<int64_t>(read(reinterpret_cast<const unsigned char*>(iv.data()) + ioff + size_t(k) * size_t(ics), ict));
                if (target < 0 || target >= n) return out = {}, out;
                for (int c = 0; c < nc; ++c)
                    out[size_t(target) * size_t(nc) + size_t(c)] =
                        read(reinterpret_cast<const unsigned char*>(vv.data()) + voff + size_t(k * nc + c) * size_t(cs), ct);
            }
        }
        return out;
    }

    void check_accessor(size_t i) {
        const json& a = d_["accessors"][i];
        if (!a.is_object()) return;  // the structure checks name it
        const std::string p = at("accessors", i);
        const std::vector<double>& v = values(i);
        if (v.empty()) return;
        const int nc = type_components(a.value("type", std::string()));
        const bool is_float = a.value("componentType", 0) == kFloat;
        if (is_float)
            for (size_t k = 0; k < v.size(); ++k)
                if (!std::isfinite(v[k])) {
                    warn(p, "element " + std::to_string(k / size_t(nc)) + " is not a finite number");
                    return;
                }
        for (const char* key : {"min", "max"}) {
            if (!a.contains(key) || !a[key].is_array() || a[key].size() != size_t(nc)) continue;
            const bool is_min = key[1] == 'i';
            for (int c = 0; c < nc; ++c) {
                double actual = is_min ? kInf : -kInf;
                for (size_t e = 0; e < v.size() / size_t(nc); ++e)
                    actual = is_min ? std::min(actual, v[e * size_t(nc) + size_t(c)]) : std::max(actual, v[e * size_t(nc) + size_t(c)]);
                double declared = a[key][size_t(c)].get<double>();
                if (is_float) declared = static_cast<float>(declared), actual = static_cast<float>(actual);
                if (declared != actual) {
                    const bool outside = is_min ? actual < declared : actual > declared;
                    warn(at(at(p, key), size_t(c)), "declared " + num(declared) + " but the data's " + (is_min ? "minimum" : "maximum") +
                                                         " is " + num(actual) + (outside ? " (elements lie outside the declared bounds)" : ""));
                    break;
                }
            }
        }
    }

    // The accessor an attribute/index refers to, if it is a valid index.
    const std::vector<double>* accessor_values(const json& v, int* nc, int64_t* ct, bool* normalized) {
        if (!v.is_number_integer() || v.get<int64_t>() < 0) return nullptr;
        const size_t a = v.get<size_t>();
        auto accessors = d_.find("accessors");
        if (accessors == d_.end() || !accessors->is_array() || a >= accessors->size() || !(*accessors)[a].is_object()) return nullptr;
        const json& acc = d_["accessors"][a];
        *nc = type_components(acc.value("type", std::string()));
        *ct = acc.value("componentType", 0);
        *normalized = acc.value("normalized", false);
        const std::vector<double>& out = values(a);
        return out.empty() ? nullptr : &out;
    }

    static double unorm(double v, int64_t ct, bool normalized) {
        if (!normalized) return v;
        switch (ct) {
            case kUByte: return v / 255.0;
            case kUShort: return v / 65535.0;
            case kByte: return std::max(v / 127.0, -1.0);
            case kShort: return std::max(v / 32767.0, -1.0);
            default: return v;
        }
    }

    void check_mesh_data() {
        // Only well-formed parts: a malformed one is the structure checks' error, and tinygltf may
        // still have read the file (a non-array "meshes" must not throw here).
        if (!d_.contains("meshes") || !d_["meshes"].is_array()) return;
        const json& meshes = d_["meshes"];
        for (size_t mi = 0; mi < meshes.size(); ++mi) {
            if (!meshes[mi].is_object() || !meshes[mi].contains("primitives") || !meshes[mi]["primitives"].is_array()) continue;
            const json& prims = meshes[mi]["primitives"];
            for (size_t pi = 0; pi < prims.size(); ++pi) {
                const json& prim = prims[pi];
                if (!prim.is_object() || !prim.contains("attributes") || !prim["attributes"].is_object()) continue;
                const std::string pp = at(at(at("meshes", mi), "primitives"), pi);
                const json& attrs = prim["attributes"];
                int nc = 0;
                int64_t ct = 0;
                bool norm = false;
                auto unit_check = [&](const char* name, int len) {
                    if (!attrs.contains(name)) return;
                    const auto* v = accessor_values(attrs[name], &nc, &ct, &norm);
                    if (!v || nc < len) return;
                    for (size_t e = 0; e < v->size() / size_t(nc); ++e) {
                        double l2 = 0;
                        for (int c = 0; c < 3; ++c) l2 += std::pow(unorm((*v)[e * size_t(nc) + size_t(c)], ct, norm), 2);
                        if (std::isfinite(l2) && std::fabs(std::sqrt(l2) - 1.0) > 5e-3) {
                            warn(at(at(pp, "attributes"), name), "element " + std::to_string(e) + " is not a unit vector (length " +
                                                                      num(std::sqrt(l2)) + "); normalised");
                            return;
                        }
                        if (len == 4 && std::fabs(std::fabs(unorm((*v)[e * size_t(nc) + 3], ct, norm)) - 1.0) > 1e-6) {
                            warn(at(at(pp, "attributes"), name), "element " + std::to_string(e) + " has w = " +
                                                                      num((*v)[e * size_t(nc) + 3]) + ", not 1 or -1; its sign is used");
                            return;
                        }
                    }
                };
                unit_check("NORMAL", 3);
                unit_check("TANGENT", 4);
                for (auto it = attrs.begin(); it != attrs.end(); ++it) {
                    const std::string& name = it.key();
                    const std::string ap = at(at(pp, "attributes"), name);
                    if (set_index(name, "COLOR_") >= 0) {
                        const auto* v = accessor_values(*it, &nc, &ct, &norm);
                        if (v && ct == kFloat)
                            for (double x : *v)
                                if (x < 0 || x > 1) {
                                    warn(ap, "colour component " + num(x) + " is outside [0, 1]");
                                    break;
                                }
                    }
                    if (const int w = set_index(name, "WEIGHTS_"); w >= 0) check_weights(attrs, w, ap);
                }
                if (prim.contains("indices")) {
                    const auto* v = accessor_values(prim["indices"], &nc, &ct, &norm);
                    const double restart = ct == kUByte ? 255 : ct == kUShort ? 65535 : 4294967295.0;
                    if (v)
                        for (double x : *v)
                            if (x == restart) {
                                warn(at(pp, "indices"), "contains the primitive restart value " + num(restart));
                                break;
                            }
                }
            }
        }
    }

    // Skin weights (spec 3.7.3.3): non-negative; a joint appears once per vertex with a non-zero
    // weight. Warnings: the loader clamps negative weights to 0 and normalises the sums.
    void check_weights(const json& attrs, int set, const std::string& path) {
        if (set != 0) return;  // all sets are summed together, once
        std::vector<const std::vector<double>*> ws, js;
        std::vector<std::pair<int64_t, bool>> wfmt;
        for (int s = 0;; ++s) {
            const std::string wn = "WEIGHTS_" + std::to_string(s), jn = "JOINTS_" + std::to_string(s);
            if (!attrs.contains(wn)) break;
            int nc = 0;
            int64_t ct = 0;
            bool norm = false;
            const auto* w = accessor_values(attrs[wn], &nc, &ct, &norm);
            if (!w || nc != 4) return;
            ws.push_back(w);
            wfmt.emplace_back(ct, norm);
            const auto* j = attrs.contains(jn) ? accessor_values(attrs[jn], &nc, &ct, &norm) : nullptr;
            js.push_back(j && nc == 4 && j->size() == w->size() ? j : nullptr);
        }
        if (ws.empty()) return;
        const size_t n = ws[0]->size() / 4;
        for (size_t e = 0; e < n; ++e) {
            double sum = 0;
            std::set<double> joints;
            for (size_t s = 0; s < ws.size(); ++s) {
                if (ws[s]->size() != ws[0]->size()) return;
                for (int c = 0; c < 4; ++c) {
                    const double w = unorm((*ws[s])[e * 4 + size_t(c)], wfmt[s].first, wfmt[s].second);
                    if (w < 0) {
                        warn(path, "vertex " + std::to_string(e) + " has a negative weight " + num(w));
                        return;
                    }
                    sum += w;
                    if (js[s] && w > 0 && !joints.insert((*js[s])[e * 4 + size_t(c)]).second) {
                        warn(path, "vertex " + std::to_string(e) + " lists joint " + num((*js[s])[e * 4 + size_t(c)]) + " twice");
                        return;
                    }
                }
            }
            (void)sum;  // not checked here: the loader normalises each vertex's weights (and warns once per primitive)
        }
    }

    void check_animation_data() {
        if (!d_.contains("animations") || !d_["animations"].is_array()) return;
        const json& anims = d_["animations"];
        for (size_t ai = 0; ai < anims.size(); ++ai) {
            const json& a = anims[ai];
            if (!a.is_object() || !a.contains("samplers") || !a["samplers"].is_array()) continue;
            const json& samplers = a["samplers"];
            for (size_t si = 0; si < samplers.size(); ++si) {
                const json& s = samplers[si];
                if (!s.is_object() || !s.contains("input")) continue;
                int nc = 0;
                int64_t ct = 0;
                bool norm = false;
                const auto* in = accessor_values(s["input"], &nc, &ct, &norm);
                const std::string sp = at(at(at("animations", ai), "samplers"), si);
                const std::string p = at(sp, "input");
                // Errors: the times must be finite and strictly increasing (sampling searches them),
                // the output values finite.
                bool negative = false;
                if (in && nc == 1)
                    for (size_t k = 0; k < in->size(); ++k) {
                        if (!std::isfinite((*in)[k])) {
                            error(p, "keyframe " + std::to_string(k) + ": time " + num((*in)[k]) + " is not a finite number");
                            break;
                        }
                        if (k > 0 && !((*in)[k] > (*in)[k - 1])) {
                            error(p, "keyframe times are not strictly increasing (keyframe " + std::to_string(k) + ": " + num((*in)[k]) +
                                         " after " + num((*in)[k - 1]) + ")");
                            break;
                        }
                        if ((*in)[k] < 0 && !negative) {
                            warn(p, "keyframe time " + num((*in)[k]) + " is negative");
                            negative = true;
                        }
                    }
                if (!s.contains("output")) continue;
                const auto* out = accessor_values(s["output"], &nc, &ct, &norm);
                if (out && ct == kFloat)
                    for (size_t k = 0; k < out->size(); ++k)
                        if (!std::isfinite((*out)[k])) {
                            error(at(sp, "output"), "element " + std::to_string(k / size_t(std::max(nc, 1))) + " is not a finite number");
                            break;
                        }
            }
            if (!a.contains("channels") || !a["channels"].is_array()) continue;
            for (size_t ci = 0; ci < a["channels"].size(); ++ci) {
                const json& c = a["channels"][ci];
                if (!c.is_object() || !c.contains("target") || !c["target"].is_object() || c["target"].value("path", "") != "rotation") continue;
                if (!c.contains("sampler") || !c["sampler"].is_number_integer() || c["sampler"].get<size_t>() >= samplers.size()) continue;
                const json& s = samplers[c["sampler"].get<size_t>()];
                if (!s.is_object() || !s.contains("output")) continue;
                int nc = 0;
                int64_t ct = 0;
                bool norm = false;
                const auto* out = accessor_values(s["output"], &nc, &ct, &norm);
                if (!out || nc != 4) continue;
                const bool cubic = s.value("interpolation", "") == "CUBICSPLINE";
                for (size_t e = 0; e < out->size() / 4; ++e) {
                    if (cubic && e % 3 != 1) continue;  // in- and out-tangents need not be unit
                    double l2 = 0;
                    for (int k = 0; k < 4; ++k) l2 += std::pow(unorm((*out)[e * 4 + size_t(k)], ct, norm), 2);
                    if (std::fabs(std::sqrt(l2) - 1.0) > 5e-3) {
                        warn(at(at(at("animations", ai), "channels"), ci) + ".sampler",
                             "rotation keyframe " + std::to_string(e) + " is not a unit quaternion (length " + num(std::sqrt(l2)) + ")");
                        break;
                    }
                }
            }
        }
    }

    void check_skin_data() {
        if (!d_.contains("skins") || !d_["skins"].is_array()) return;
        const json& skins = d_["skins"];
        for (size_t i = 0; i < skins.size(); ++i) {
            if (!skins[i].is_object() || !skins[i].contains("inverseBindMatrices")) continue;
            int nc = 0;
            int64_t ct = 0;
            bool norm = false;
            const auto* m = accessor_values(skins[i]["inverseBindMatrices"], &nc, &ct, &norm);
            if (!m || nc != 16) continue;
            for (size_t e = 0; e < m->size() / 16; ++e) {
                const double* x = m->data() + e * 16;
                if (x[3] != 0 || x[7] != 0 || x[11] != 0 || x[15] != 1) {
                    warn(at(at("skins", i), "inverseBindMatrices"), "matrix " + std::to_string(e) + " is not affine (last row 0 0 0 1)");
                    break;
                }
            }
        }
    }

    const json& d_;
    const std::vector<std::string_view>& buffers_;
    std::map<size_t, std::vector<double>> cache_;
    std::vector<Issue> issues_;
};

uint32_t u32(std::string_view b, size_t at) {
    uint32_t v;
    std::memcpy(&v, b.data() + at, 4);
    return v;  // glTF is little-endian, as is every platform Candela builds on
}

}  // namespace

bool buffer_available(const nlohmann::json& buffer, bool glb, size_t index) {
    if (!buffer.is_object()) return false;
    auto uri = buffer.find("uri");
    if (uri == buffer.end()) return glb && index == 0;
    if (!uri->is_string()) return false;
    const std::string u = uri->get<std::string>();
    return starts_with(u, "data:") || uri_problem(u).empty();
}

bool extension_implemented(std::string_view name) {
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
    return Validator(doc, glb, glb_bin_size).run();
}

std::vector<Issue> validate_data(const nlohmann::json& doc, const std::vector<std::string_view>& buffers) {
    return DataChecker(doc, buffers).run();
}

std::vector<IgnoredFeature> ignored_features(const nlohmann::json& doc) {
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
