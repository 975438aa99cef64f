// glTF validation of meshes: primitives, their attributes and indices, morph targets (spec 3.7.2).
#include "scene/gltf_validate_internal.hpp"

#include <cmath>

namespace candela::gltf::validation {

// An accessor Candela reads must have a known format and data it can get.
bool Validator::unusable(int64_t a, const std::string& path) {
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

// Formats from the spec's table of mesh attributes (3.7.2.1), widened by KHR_mesh_quantization.
std::string Validator::attribute_format_problem(const std::string& name, const AccessorInfo& a) const {
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

bool Validator::known_semantic(const std::string& name) {
    if (name == "POSITION" || name == "NORMAL" || name == "TANGENT") return true;
    for (const char* p : {"TEXCOORD_", "COLOR_", "JOINTS_", "WEIGHTS_"})
        if (set_index(name, p) >= 0) return true;
    return !name.empty() && name[0] == '_';
}

// Attributes Candela reads; the others (TEXCOORD_2+, COLOR_1+, custom) it ignores.
bool Validator::read_by_candela(const std::string& name) {
    return name == "POSITION" || name == "NORMAL" || name == "TANGENT" || name == "TEXCOORD_0" || name == "TEXCOORD_1" ||
           name == "COLOR_0" || set_index(name, "JOINTS_") >= 0 || set_index(name, "WEIGHTS_") >= 0;
}

Validator::MaterialNeeds Validator::material_needs(int64_t m) const {
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

void Validator::check_meshes() {
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
size_t Validator::check_primitive(const json& prim, const std::string& pp) {
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
    const auto mode = integer(prim, "mode", pp, false, 0, 6);
    // KHR_draco_mesh_compression (its specification): the stream's bufferView, and a Draco
    // attribute id per semantic of the primitive's `attributes`. The loader decodes it
    // (gltf_draco.cpp) into the accessors `attributes` and `indices` name; it reads triangles.
    if (const json* e = get(prim, "extensions"); e && e->is_object())
        if (const json* d = get(*e, "KHR_draco_mesh_compression"); d && d->is_object()) {
            const std::string dp = at(at(pp, "extensions"), "KHR_draco_mesh_compression");
            const int64_t view = ref(*d, "bufferView", dp, "bufferViews", true);
            if (view >= 0 && views_[static_cast<size_t>(view)].unavailable)
                problem(at(dp, "bufferView"), "bufferView " + std::to_string(view) + " lies in a buffer whose data is not available");
            const json* da = get(*d, "attributes");
            if (!da || !da->is_object() || da->empty()) {
                problem(dp, "needs a non-empty 'attributes' object (attribute semantic -> Draco attribute id)");
            } else {
                for (auto it = da->begin(); it != da->end(); ++it) {
                    const std::string ip = at(at(dp, "attributes"), it.key());
                    if (!it->is_number_integer() || it->get<int64_t>() < 0) problem(ip, "must be a Draco attribute id (a non-negative integer), not " + it->dump());
                    else if (!base.count(it.key())) problem(ip, "the primitive has no " + it.key() + " attribute to decode into");
                }
            }
            if (!get(prim, "indices")) problem(pp, "a Draco-compressed primitive needs 'indices' (Candela decodes triangle meshes)");
            if (mode && *mode != 4) problem(at(pp, "mode"), std::to_string(*mode) + ": Candela decodes Draco-compressed TRIANGLES (4) only");
        }
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

}  // namespace candela::gltf::validation
