// The glTF validator's shared helpers: JSON paths, component formats, URIs, object kinds.
#include "scene/gltf_validate_internal.hpp"

#include <cctype>
#include <cstdio>
#include <cstring>
#include <map>

namespace candela::gltf::validation {

std::string at(const std::string& base, const std::string& key) { return base.empty() ? key : base + "." + key; }
std::string at(const std::string& base, size_t i) { return base + "[" + std::to_string(i) + "]"; }

std::string num(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", v);
    return buf;
}

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

std::string base64_encode(std::string_view bytes) {
    static const char* abc = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    out.reserve((bytes.size() + 2) / 3 * 4);
    for (size_t i = 0; i < bytes.size(); i += 3) {
        uint32_t v = static_cast<uint32_t>(static_cast<uint8_t>(bytes[i])) << 16;
        if (i + 1 < bytes.size()) v |= static_cast<uint32_t>(static_cast<uint8_t>(bytes[i + 1])) << 8;
        if (i + 2 < bytes.size()) v |= static_cast<uint8_t>(bytes[i + 2]);
        out += abc[(v >> 18) & 63];
        out += abc[(v >> 12) & 63];
        out += i + 1 < bytes.size() ? abc[(v >> 6) & 63] : '=';
        out += i + 2 < bytes.size() ? abc[v & 63] : '=';
    }
    return out;
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

}  // namespace candela::gltf::validation
