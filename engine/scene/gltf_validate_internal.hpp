#pragma once
// Internal to the glTF validator (gltf_validate*.cpp): the shared context of its checks, i.e. the
// JSON path building, the message collection (problem/warn/error and the Soft scope), the typed
// member readers that report what they cannot read, and the facts that later checks use
// (buffer lengths, bufferViews, accessors, morph target counts, parents). The checks themselves
// are split by glTF object kind, one file each; the class is one so that they share that state.
// Not part of the engine's interface: include only from the validator's files.
#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "scene/gltf_validate.hpp"

// Rules: the glTF 2.0 specification (Khronos, 2021), sections 3.6-3.12 and 5 (Properties
// Reference), and the specifications of the KHR extensions named below. Codes in comments are
// glTF-Validator's issue codes for the same rule, to make the mapping easy to audit.
namespace candela::gltf::validation {

using json = nlohmann::json;

// ---- JSON paths, numbers and formats (gltf_validate_common.cpp) ----

// "meshes[0].primitives[1]": a member of `base`, an element of `base`.
std::string at(const std::string& base, const std::string& key);
std::string at(const std::string& base, size_t i);

// A number as messages print it (%g).
std::string num(double v);

constexpr double kPi = 3.14159265358979323846;
constexpr double kInf = std::numeric_limits<double>::infinity();

constexpr int kByte = 5120, kUByte = 5121, kShort = 5122, kUShort = 5123, kUInt = 5125, kFloat = 5126;
constexpr int64_t kArrayBuffer = 34962, kElementArrayBuffer = 34963;

int component_size(int64_t ct);
const char* component_name(int64_t ct);
int type_components(const std::string& t);
// Bytes of one element: matrix columns start on 4-byte boundaries (spec 3.6.2.4, data alignment).
int64_t element_size(int64_t ct, const std::string& type);

bool starts_with(std::string_view s, std::string_view p);
bool ends_with(std::string_view s, std::string_view p);
// "TEXCOORD_3" -> 3 for prefix "TEXCOORD_"; -1 if `name` is not prefix + a set index (no leading zeros).
int set_index(const std::string& name, const char* prefix);

// ---- URIs (gltf_validate_common.cpp) ----

bool valid_base64(std::string_view s, size_t* decoded);
// RFC 4648 base64 with '=' padding: the payload of the data URIs the loader and writer make.
std::string base64_encode(std::string_view bytes);
// The size of a data URI's non-base64 payload (RFC 2397: percent-encoded octets).
bool percent_decoded_size(std::string_view s, size_t* decoded);
// A data: URI "data:[<media type>][;base64],<data>": its media type and base64 payload.
struct DataUri {
    std::string media_type;
    std::string_view payload;
    bool base64 = false;
};
std::optional<DataUri> parse_data_uri(std::string_view uri);
// Why a URI that is not data: cannot be read; empty when it is a relative reference.
std::string uri_problem(std::string_view uri);

// ---- Object kinds (gltf_validate_common.cpp) ----

// The kind of a JSON object reached by `key` from an object of kind `parent`.
std::string child_kind(const std::string& parent, const std::string& key);
// Visits every object that can carry `extensions`, with its kind; `extras` are not entered.
void walk(const json& v, const std::string& path, const std::string& kind,
          const std::function<void(const json&, const std::string&, const std::string&)>& visit);

// ---- What the checks learn about accessors and bufferViews ----

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

// The document checks (validate_document). Members defined in the class are the shared
// context; the checks are defined in the file named above each group.
class Validator {
public:
    Validator(const json& doc, bool glb, int64_t bin) : d_(doc), glb_(glb), bin_(bin) {}

    std::vector<Issue> run();

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

    // The checks, one file per kind of glTF object. run() calls them in a fixed order, which is
    // the order of the messages.
    // gltf_validate.cpp
    void check_root();
    void check_asset();

    // gltf_validate_extensions.cpp
    void check_extension_declarations();
    void check_lights();
    void check_variants();

    // gltf_validate_buffers.cpp: buffers, bufferViews, accessors
    void check_buffers();
    void check_buffer_views();
    void check_fits(int64_t view, int64_t offset, int64_t elem, int64_t stride, int64_t n, int64_t csize, const std::string& path,
                    int64_t last_elem = -1);
    // Set while checking an accessor's own data: the problem is reported where the accessor is
    // used (a mesh attribute names the primitive), or at the accessor when nothing reads it.
    std::string* out_of_bounds = nullptr;
    void check_accessors();

    // gltf_validate_materials.cpp: images, samplers, textures, materials
    void check_images();
    void check_samplers();
    void check_textures();
    void check_texture_info(const json& ti, const std::string& p);
    void check_materials();

    // gltf_validate_meshes.cpp: meshes, primitives, morph targets
    bool unusable(int64_t a, const std::string& path);
    std::string attribute_format_problem(const std::string& name, const AccessorInfo& a) const;
    static bool known_semantic(const std::string& name);
    static bool read_by_candela(const std::string& name);
    // texCoord sets and normal maps a material asks of a primitive.
    struct MaterialNeeds {
        std::vector<std::pair<int64_t, std::string>> texcoords;  // (set, JSON path of the textureInfo)
        std::string normal_map;                                  // path of a normal texture, if any
    };
    MaterialNeeds material_needs(int64_t m) const;
    void check_meshes();
    size_t check_primitive(const json& prim, const std::string& pp);

    // gltf_validate_nodes.cpp: cameras, nodes, scenes, skins
    void check_cameras();
    void check_nodes();
    void check_node_loops();
    void check_scenes();
    void check_skinned_nodes_in_scenes();
    int64_t root_of(int64_t n) const;
    bool is_ancestor_or_self(int64_t a, int64_t n) const;
    void check_skins();

    // gltf_validate_animations.cpp
    void check_animations();

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

}  // namespace candela::gltf::validation
