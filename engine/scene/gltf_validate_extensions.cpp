// glTF validation of extensions: extensionsUsed/extensionsRequired, where each extension may
// appear, the value ranges of material extensions Candela does not implement, and the two
// extensions with top-level data (KHR_lights_punctual, KHR_materials_variants).
#include "scene/gltf_validate_internal.hpp"

#include <algorithm>
#include <cstring>

namespace candela::gltf::validation {
namespace {

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

// Value ranges of the material extensions Candela does not implement (the loader range-checks
// the ones it does). From each extension's JSON schema.
struct Range {
    const char* ext;
    const char* key;
    double lo, hi;
    bool lo_exclusive;
};
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

}  // namespace

// extensionsUsed / extensionsRequired, and every `extensions` object in the file.
void Validator::check_extension_declarations() {
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

// KHR_lights_punctual (its spec and schema): lights at the top level, nodes refer to them.
void Validator::check_lights() {
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

// KHR_materials_variants (its spec): names at the top level, mappings on primitives.
void Validator::check_variants() {
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

}  // namespace candela::gltf::validation
